// PNG through libpng: decoding from memory into a Raster, and writing (8 or 16 bits, 1 to 4
// channels) with text metadata. libpng reports errors by longjmp; every libpng call here runs inside a small
// function that holds only plain data, so a jump never crosses a C++ destructor.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "io/raster.h"

namespace clpt {

// Decodes a PNG (its chunks already checked by check_png_chunks): palette and grey below 8
// bits expand to 8 bits, tRNS to an alpha channel; 16-bit samples are kept (U16) where
// `keep16`, else rounded to 8 bits. No gamma or colour conversion. Rows grow a strip at a time
// (an interlaced image is allocated whole, within `check`'s limits). False with `fail` set.
bool decode_png(const unsigned char* data, size_t size, bool keep16, const SizeCheck& check, Raster* out,
                DecodeFailure* fail);

// Writes width x height pixels of `channels` samples (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA)
// of `bits` 8 or 16 (16-bit samples in native byte order), top row first, to `file`, with each
// (key, text) pair as a tEXt chunk. False with `why` set.
bool write_png(const std::filesystem::path& file, uint32_t width, uint32_t height, uint32_t channels, int bits,
               const void* samples, const std::vector<std::pair<std::string, std::string>>& text,
               std::string* why);

}  // namespace clpt
