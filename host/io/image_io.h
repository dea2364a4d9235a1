// Image files through OpenImageIO. EXR: linear float RGB with metadata. PNG/JPEG: sRGB,
// 8 bits, clamped. Every write goes to a temporary file in the same folder and is renamed
// over the destination only once complete, so a failure never leaves a half-written image
// or destroys an existing one.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "io/image.h"

namespace clpt {

struct ImageMetadata {
  std::vector<std::pair<std::string, std::string>> strings;
  std::vector<std::pair<std::string, int>> ints;
  std::vector<std::pair<std::string, float>> floats;
};

// Checks the output path before any rendering: a known extension (.exr, .png, .jpg, .jpeg)
// and a folder that exists and is writable. Throws Error(Usage) or Error(Output).
void check_output_path(const std::filesystem::path& path);

// Throws Error(ExitCode::Output) naming the file when it cannot be written.
void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& meta);

// Reads any image OIIO can read as linear float RGB (8-bit files are decoded from sRGB).
// Throws Error(ExitCode::BadInput) naming the file.
Image read_image(const std::filesystem::path& path);

}  // namespace clpt
