// WebP (EXT_texture_webp) through libwebp: decoding from memory into a Raster, 8-bit RGB or
// RGBA (straight alpha).
#pragma once

#include <cstddef>

#include "io/raster.h"

namespace clpt {

// Decodes a still WebP (lossy or lossless; an animation is refused) whose RIFF size the
// caller has checked against the data. The image is decoded whole, within `check`'s limits.
bool decode_webp(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail);

}  // namespace clpt
