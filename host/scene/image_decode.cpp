#include "scene/image_decode.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <utility>

#include "io/image_bytes.h"
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
  const char* format = oiio_format_name(kind);
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
  auto too_large = [&](uint64_t w, uint64_t h) {
    std::string refusal = image_size_refusal(w, h, max_dimension, max_pixels, "--limit image-dimension=N, image-pixels=N");
    if (refusal.empty()) return false;
    *why = std::move(refusal);
    return true;
  };
  // The size from the header first: a decoder may allocate the whole image when it opens it.
  uint64_t header_w = 0, header_h = 0;
  if (image_header_size(data, size, &header_w, &header_h) && too_large(header_w, header_h)) return false;
  // Embedded ICC profiles out (OpenImageIO 2.4 crashes on a damaged JPEG one).
  std::vector<unsigned char> clean;
  if (!without_icc_profiles(data, size, kind, &clean, why)) return false;
  try {
    OIIO::Filesystem::IOMemReader proxy(clean.data(), clean.size());
    // Straight alpha, as glTF means it (OIIO would otherwise premultiply PNG alpha).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(format);
    if (!in) {
      *why = std::string("OpenImageIO has no ") + format + " reader: " + one_line(OIIO::geterror());
      return false;
    }
    const std::string name = std::string("image.") + format;
    OIIO::ImageSpec spec;
    if (!in->open(name, spec, config)) {
      std::string e = one_line(in->geterror());
      *why = std::string("cannot decode the ") + format + " data" + (e.empty() ? "" : ": " + e);
      return false;
    }
    spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels <= 0) {
      *why = "the " + std::string(format) + " header gives a size of " + std::to_string(spec.width) + "x" +
             std::to_string(spec.height);
      return false;
    }
    const uint64_t w = uint64_t(spec.width), h = uint64_t(spec.height);
    if (too_large(w, h)) return false;
    // A JPEG whose header claims more pixels than its bytes can code: Huffman coding spends
    // at least 2 bits on every 8 x 8 block of the first component (a 1-bit DC code and a
    // 1-bit end of block), w h / 256 bytes; with a margin of 4, fewer than w h / 1024 bytes
    // is a lying header. libjpeg pads such an image with grey and OIIO reports success
    // (issue 23, class 7: an 8x8 JPEG claiming 16384x4096 rendered, 977 MB, exit 0).
    if (kind == ImageFormat::Jpeg && jpeg_is_huffman(data, size) && uint64_t(size) * 1024 < w * h) {
      *why = "the JPEG header gives a size of " + std::to_string(w) + "x" + std::to_string(h) +
             ", more than its " + std::to_string(size) + " bytes can hold (a damaged or lying header)";
      return false;
    }
    const int nc = spec.nchannels;
    const int keep = nc > 4 ? 4 : nc;
    const bool wide = keep16 && spec.format == OIIO::TypeDesc::UINT16;
    const OIIO::TypeDesc type = wide ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
    const size_t bytes = wide ? 2 : 1;
    std::vector<unsigned char> pixels(size_t(w * h) * size_t(keep) * bytes);
    // A decoder that reports a problem and still returns pixels (libjpeg pads a JPEG whose
    // data ends early with grey) has read a damaged image.
    if (!in->read_image(0, 0, 0, keep, type, pixels.data()) || in->has_error()) {
      std::string e = one_line(in->geterror());
      *why = std::string("cannot decode the ") + format + " pixels" + (e.empty() ? "" : ": " + e);
      return false;
    }
    in->close();
    out->width = uint32_t(w);
    out->height = uint32_t(h);
    out->wide = wide;
    out->texels.resize(size_t(w * h) * (wide ? 2 : 1));
    const uint32_t opaque = wide ? 65535u : 255u;
    for (size_t i = 0; i < size_t(w * h); ++i) {
      uint32_t c[4] = {0, 0, 0, opaque};
      for (int k = 0; k < keep; ++k) {
        const size_t at = (i * size_t(keep) + size_t(k)) * bytes;
        uint16_t v16 = 0;
        if (wide) std::memcpy(&v16, &pixels[at], 2);  // native order, as OpenImageIO writes it
        c[k] = wide ? v16 : pixels[at];
      }
      if (keep <= 2) {  // grey (and alpha)
        if (keep == 2) c[3] = c[1];
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
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    *why = std::string("cannot decode the image: ") + e.what();
    return false;
  }
}

DecodedImage placeholder_image() {
  DecodedImage img;
  img.width = img.height = 1;
  img.texels = {0xFFFF00FFu};  // R 255, G 0, B 255, A 255
  return img;
}

}  // namespace clpt
