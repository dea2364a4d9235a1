// Portable float maps (.pfm), the format Intel Open Image Denoise's oidnDenoise reads
// (--hdr, --alb, --nrm): a text header "PF\nW H\n-1.0\n" (-1: little-endian floats), then
// RGB float32 rows from the bottom row up.
#pragma once

#include <filesystem>

#include "io/image.h"

namespace clpt {

// Writes atomically (temporary file, rename); Error(ExitCode::Output) naming the file when it
// cannot be written.
void write_pfm(const std::filesystem::path& path, const Image& image);

}  // namespace clpt
