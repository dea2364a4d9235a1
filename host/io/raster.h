// A decoded image as its file held it, before clpt converts it: rows top to bottom, channels
// interleaved, one sample type. The format decoders (io/png_codec, jpeg_codec, webp_codec,
// hdr_codec, exr_codec) produce it; io/image_io (linear float RGB) and scene/image_decode
// (RGBA8/16 texels) convert it. The decoders call the libraries' C APIs directly (libpng,
// libjpeg-turbo, libwebp, OpenEXR): a process that reads or writes images loads those few
// libraries, not OpenImageIO's 260 (docs/BENCHMARKS.md, session 43).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace clpt {

enum class SampleType { U8, U16, F32 };

struct Raster {
  uint32_t width = 0, height = 0, channels = 0;  // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA (EXR: any)
  SampleType type = SampleType::U8;
  std::vector<unsigned char> bytes;  // the samples, native byte order

  size_t sample_bytes() const { return type == SampleType::U8 ? 1 : type == SampleType::U16 ? 2 : 4; }
  size_t row_bytes() const { return size_t(width) * channels * sample_bytes(); }
  size_t samples() const { return size_t(width) * height * channels; }
  // Sample i as stored (an integer's code value; a float's bits as a float).
  uint32_t code(size_t i) const {
    if (type == SampleType::U8) return bytes[i];
    uint16_t v = 0;
    std::memcpy(&v, &bytes[2 * i], 2);
    return v;
  }
  // Sample i as a float: integers scaled to [0, 1], floats as stored.
  float value(size_t i) const {
    if (type == SampleType::F32) {
      float f;
      std::memcpy(&f, &bytes[4 * i], 4);
      return f;
    }
    return type == SampleType::U8 ? float(bytes[i]) * (1.0f / 255.0f) : float(code(i)) * (1.0f / 65535.0f);
  }
};

// Why a decoder stopped: `row` is the first row it could not decode, or -1 where the header
// (or anything before the first row) failed.
struct DecodeFailure {
  std::string what;
  int64_t row = -1;

  // Records the reason and the row; false, for a decoder's `return fail->set(...)`.
  bool set(std::string reason, int64_t at_row) {
    what = std::move(reason);
    row = at_row;
    return false;
  }
};

// Called with the header's size before any pixel memory is allocated; a non-empty return
// refuses the image with that reason (image_size_refusal's message).
using SizeCheck = std::function<std::string(uint64_t width, uint64_t height)>;

// Rows a decoder adds at a time: pixel memory grows by this many rows as they are decoded, so
// a header that lies about the height costs no more than the rows really there.
inline constexpr uint32_t kDecodeStripRows = 64;

}  // namespace clpt
