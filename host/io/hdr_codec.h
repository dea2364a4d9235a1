// Radiance HDR (RGBE, Ward 1991) decoding from memory into a Raster of float RGB: clpt's own
// reader, since no Debian library reads the format alone (OpenImageIO's reader is its own
// code too). Flat, old-style run-length and new-style (per-component) run-length scanlines.
#pragma once

#include <cstddef>

#include "io/raster.h"

namespace clpt {

// The file's size from its header alone ("#?" signature, lines up to an empty one, then the
// resolution "-Y H +X W"). False with `why` set where the header is damaged or another
// orientation (clpt reads only the standard one).
bool hdr_header_size(const unsigned char* data, size_t size, uint64_t* width, uint64_t* height, std::string* why);

// Decodes the pixels: an RGBE texel (m, e) is m 2^(e - 136) per component, 0 where e is 0.
// Rows grow a strip at a time; data that ends early fails at its row.
bool decode_hdr(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail);

}  // namespace clpt
