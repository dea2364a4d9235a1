// A linear RGB float image in scanline order, top row first.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace clpt {

// The largest width or height of a film (--resolution, a camera's default image, a
// checkpoint, a --reference image).
inline constexpr uint32_t kMaxFilmSide = 16384;

struct Image {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // 3 floats per pixel

  Image() = default;
  Image(uint32_t w, uint32_t h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}
  float* pixel(uint32_t x, uint32_t y) { return &rgb[(size_t(y) * width + x) * 3]; }
  const float* pixel(uint32_t x, uint32_t y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

// An image file's attributes (EXR header attributes, PNG text chunks), e.g. "clpt:spp".
struct ImageMetadata {
  std::vector<std::pair<std::string, std::string>> strings;
  std::vector<std::pair<std::string, int>> ints;
  std::vector<std::pair<std::string, float>> floats;
};

}  // namespace clpt
