// JPEG through libjpeg-turbo: decoding from memory into a Raster (grey or RGB, 8 bits), and
// 8-bit RGB writing. libjpeg reports errors by longjmp; as in io/png_codec, every library call
// runs inside a small function that holds only plain data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "io/raster.h"

namespace clpt {

// Decodes a baseline or progressive JPEG (its marker segments already walked by
// without_icc_profiles) with libjpeg's defaults (integer IDCT, fancy upsampling): one
// channel for a greyscale file, three (RGB) for the rest; CMYK files are refused. A warning
// (libjpeg pads data that ends early with grey and only warns) fails the decode as an error
// does, at the first strip where it appears. False with `fail` set.
bool decode_jpeg(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail);

// Writes width x height 8-bit RGB pixels to `file` at `quality` (1 to 100). False with `why`.
bool write_jpeg(const std::filesystem::path& file, uint32_t width, uint32_t height, const unsigned char* rgb,
                int quality, std::string* why);

}  // namespace clpt
