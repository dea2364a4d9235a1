#include "scene/image_decode.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <utility>

#include "io/image_bytes.h"
#include "io/jpeg_codec.h"
#include "io/png_codec.h"
#include "io/webp_codec.h"
#include "util/text.h"

namespace clpt {

bool decode_image(const unsigned char* data, size_t size, DecodedImage* out, std::string* why,
                  uint64_t max_dimension, uint64_t max_pixels, bool keep16) {
  const ImageFormat kind = sniff_image(data, size);
  if (kind != ImageFormat::Png && kind != ImageFormat::Jpeg && kind != ImageFormat::Webp) {
    *why = size == 0                  ? "the image is empty (0 bytes)"
           : kind == ImageFormat::Ktx2 ? "a KTX2 (Basis Universal) image, which clpt cannot decode (Debian packages no "
                                         "KTX2 transcoder; give the texture a PNG or JPEG source)"
                                       : "not a PNG, JPEG or WebP image (unknown signature)";
    return false;
  }
  const char* format = image_format_name(kind);
  if (kind == ImageFormat::Png && !check_png_chunks(data, size, why)) return false;
  // WebP: a RIFF container whose size field covers the file (libwebp reads past a short one).
  const uint64_t riff_bytes =  // RIFF's size field (little-endian) plus its own 8 bytes
      kind == ImageFormat::Webp ? (uint64_t(data[4]) | uint64_t(data[5]) << 8 | uint64_t(data[6]) << 16 |
                                   uint64_t(data[7]) << 24) + 8
                                : 0;
  if (kind == ImageFormat::Webp && riff_bytes > size) {
    *why = "truncated WebP: the RIFF header gives " + std::to_string(riff_bytes) +
           " bytes, the data has " + std::to_string(size);
    return false;
  }
  std::string refusal;  // the size check's, passed on as it is
  const SizeCheck check = [&](uint64_t w, uint64_t h) {
    refusal = image_size_refusal(w, h, max_dimension, max_pixels, "--limit image-dimension=N, image-pixels=N");
    return refusal;
  };
  // The size from the header first: a decoder may allocate the whole image when it opens it.
  uint64_t header_w = 0, header_h = 0;
  const bool header = image_header_size(data, size, &header_w, &header_h);
  if (header && !check(header_w, header_h).empty()) {
    *why = refusal;
    return false;
  }
  // A JPEG whose header claims more pixels than its bytes can code: Huffman coding spends
  // at least 2 bits on every 8 x 8 block of the first component (a 1-bit DC code and a
  // 1-bit end of block), w h / 256 bytes; with a margin of 4, fewer than w h / 1024 bytes
  // is a lying header. libjpeg pads such an image with grey and only warns (issue 23, class
  // 7: an 8x8 JPEG claiming 16384x4096 rendered, 977 MB, exit 0).
  if (kind == ImageFormat::Jpeg && header && jpeg_is_huffman(data, size) &&
      uint64_t(size) * 1024 < header_w * header_h) {
    *why = "the JPEG header gives a size of " + std::to_string(header_w) + "x" + std::to_string(header_h) +
           ", more than its " + std::to_string(size) + " bytes can hold (a damaged or lying header)";
    return false;
  }
  // Embedded ICC profiles out (clpt manages no colour; OpenImageIO 2.4, clpt's decoder before
  // session 43, crashed on a damaged JPEG one).
  std::vector<unsigned char> clean;
  if (!without_icc_profiles(data, size, kind, &clean, why)) return false;
  Raster r;
  DecodeFailure f;
  const bool ok = kind == ImageFormat::Png    ? decode_png(clean.data(), clean.size(), keep16, check, &r, &f)
                  : kind == ImageFormat::Jpeg ? decode_jpeg(clean.data(), clean.size(), check, &r, &f)
                                              : decode_webp(clean.data(), clean.size(), check, &r, &f);
  if (!ok) {
    *why = !refusal.empty() ? refusal
                            : std::string("cannot decode the ") + format + (f.row < 0 ? " data: " : " pixels: ") + f.what;
    return false;
  }
  const size_t w = r.width, h = r.height, nc = r.channels;
  const bool wide = r.type == SampleType::U16;  // only where keep16
  out->width = r.width;
  out->height = r.height;
  out->wide = wide;
  out->texels.resize(w * h * (wide ? 2 : 1));
  const uint32_t opaque = wide ? 65535u : 255u;
  for (size_t i = 0; i < w * h; ++i) {
    uint32_t c[4] = {0, 0, 0, opaque};
    for (size_t k = 0; k < nc && k < 4; ++k) c[k] = r.code(i * nc + k);
    if (nc <= 2) {  // grey (and alpha)
      if (nc == 2) c[3] = c[1];
      c[1] = c[2] = c[0];
    }
    if (wide) {
      out->texels[2 * i] = c[0] | c[1] << 16;
      out->texels[2 * i + 1] = c[2] | c[3] << 16;
    } else {
      out->texels[i] = c[0] | c[1] << 8 | c[2] << 16 | c[3] << 24;
    }
  }
  return true;
}

DecodedImage placeholder_image() {
  DecodedImage img;
  img.width = img.height = 1;
  img.texels = {0xFFFF00FFu};  // R 255, G 0, B 255, A 255
  return img;
}

}  // namespace clpt
