// OpenEXR through the OpenEXR library itself: scanline reading of a file's first part (every
// channel as float, with its names and single-valued attributes) and float writing with ZIP
// compression and metadata.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/raster.h"

namespace clpt {

struct ExrImage {
  Raster raster;                    // F32, raster.channels channels in the order of `channels`
  std::vector<std::string> channels;  // OpenEXR's order (alphabetical)
  ImageMetadata meta;               // the header's string, int and float attributes
};

// Reads `file` (its headers already walked by check_exr_headers): the data window's pixels,
// a strip of rows at a time. Subsampled channels are refused. OpenEXR's exceptions become
// `fail` ("OpenEXR exception: ..."). False with `fail` set.
bool read_exr(const std::filesystem::path& file, const SizeCheck& check, ExrImage* out, DecodeFailure* fail);

// The data window's size from the header alone. False with `fail` set.
bool read_exr_size(const std::filesystem::path& file, uint64_t* width, uint64_t* height, DecodeFailure* fail);

// Writes width x height pixels of channels.size() interleaved floats, each channel FLOAT,
// ZIP-compressed, scanlines, with `meta` as attributes. False with `why` set.
bool write_exr(const std::filesystem::path& file, uint32_t width, uint32_t height,
               const std::vector<std::string>& channels, const float* pixels, const ImageMetadata& meta,
               std::string* why);

}  // namespace clpt
