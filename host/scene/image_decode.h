// PNG, JPEG and WebP decoding for textures, from bytes in memory (an external file, a data: URI or
// a GLB bufferView), through libpng, libjpeg-turbo and libwebp (io/*_codec). The glTF loader hands it bytes it has already
// range-checked; this file knows nothing of glTF.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/image_bytes.h"  // image_header_size

namespace clpt {

// Default limits against hostile images (checked from the header, before any pixel is
// decoded); the loader passes LoadLimits::image_dimension and image_pixels.
constexpr uint32_t kMaxImageDimension = 16384;            // width or height
constexpr uint64_t kMaxImagePixels = uint64_t{1} << 26;  // 64 Mpixel = 256 MiB of RGBA8

struct DecodedImage {
  uint32_t width = 0, height = 0;
  // width * height texels, row 0 at the top: RGBA8, R in the low byte; `wide`: RGBA16 in two
  // words, R | G << 16 then B | A << 16 (as Texture).
  std::vector<uint32_t> texels;
  bool wide = false;
};

// Decodes a PNG, JPEG or WebP (recognised by its first bytes, not by a name or media type) into
// 8-bit RGBA: grey becomes RGB, a missing alpha is 255 (65535), alpha stays unassociated
// (straight), no colour-space conversion. 16-bit channels are rounded to 8 bits, or kept
// (`wide` set) where `keep16`. Returns false with a one-line reason (bad bytes, not
// PNG/JPEG/WebP (KTX2 named as such), too large, decoder error). max_dimension and max_pixels:
// the limits (LoadLimits::image_dimension, image_pixels).
bool decode_image(const unsigned char* data, size_t size, DecodedImage* out, std::string* why,
                  uint64_t max_dimension = kMaxImageDimension, uint64_t max_pixels = kMaxImagePixels,
                  bool keep16 = false);

// One magenta texel: what --lenient puts in place of an image that cannot be decoded.
DecodedImage placeholder_image();

}  // namespace clpt
