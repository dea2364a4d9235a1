// Per-pixel accumulation on the device: sum, sum of squares, dropped samples, ray counts.
#pragma once

#include <cstdint>

#include "cl/buffer.h"
#include "io/image.h"

namespace clpt {

struct FilmResult {
  Image mean;          // radiance estimate per pixel
  Image variance;      // sample variance of one sample per pixel (unbiased, spp - 1 denominator)
  uint64_t samples_per_pixel = 0;
  uint64_t dropped_samples = 0;  // NaN/Inf samples discarded by the kernels
  uint64_t rays = 0;             // rays traced (closest hit and shadow)
};

class Film {
 public:
  Film(const cl::Context& ctx, uint32_t width, uint32_t height);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  size_t pixels() const { return size_t(width_) * height_; }
  cl::Buffer& sum() { return sum_; }
  cl::Buffer& sum_sq() { return sum_sq_; }
  cl::Buffer& ray_counts() { return ray_counts_; }
  size_t device_bytes() const { return sum_.size() + sum_sq_.size() + ray_counts_.size(); }

  // Reads the film back and divides by the samples taken.
  FilmResult resolve(uint64_t samples_per_pixel) const;

 private:
  uint32_t width_, height_;
  cl::Buffer sum_, sum_sq_, ray_counts_;
};

}  // namespace clpt
