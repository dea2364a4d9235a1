// Per-pixel accumulation on the device: sum, sum of squares, dropped samples, ray counts,
// and for splatting integrators (lt) a splat film that any work-item adds to atomically.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cl/buffer.h"
#include "render/cluster.h"
#include "io/image.h"

namespace clpt {

struct FilmResult {
  Image mean;          // radiance estimate per pixel
  Image variance;      // sample variance of one sample per pixel (unbiased, spp - 1 denominator)
  // False for splatted films (lt): a pixel's splats are not one sample per path, so there is
  // no per-pixel sample variance; `variance` is then all zero and must not be used.
  bool variance_available = true;
  uint64_t samples_per_pixel = 0;
  uint64_t dropped_samples = 0;  // NaN/Inf samples discarded by the kernels
  uint64_t rays = 0;             // rays traced (closest hit and shadow)
};

// A film's sums read back to the host. Several devices' films (and MPI ranks') add up to one
// in a fixed order (add), and that sum resolves as one device's film would.
struct FilmSums {
  uint32_t width = 0, height = 0;
  bool splats = false, sums_samples = true;  // as the Film's
  std::vector<std::array<float, 4>> sum, sum_sq, splat;  // splat: only with splats
  std::vector<uint32_t> rays;
  // Adds another film of the same size and kind, pixel by pixel, in float as the device does.
  void add(const FilmSums& other);
  // Its arrays as pieces to send (render/cluster.h), and a chunk of another film's piece
  // added as add() does.
  std::vector<Cluster::Piece> pieces() const;
  void add_chunk(size_t piece, size_t offset, const void* chunk, size_t bytes);
};

// The mean, variance and counts of `sums` after `samples_per_pixel` samples.
FilmResult resolve_film(const FilmSums& sums, uint64_t samples_per_pixel);

class Film {
 public:
  // splats: also allocate the splat film (kernels/film/splat.cl); its sums are added to the
  // per-pixel sums at resolve and normalised the same way, by samples per pixel.
  // sums_samples: false when the film holds something other than a sum of one-sample
  // estimates per pixel (sppm writes its progressive estimate times the passes): then it has
  // no per-pixel variance (nor has a splatted film).
  Film(const cl::Context& ctx, uint32_t width, uint32_t height, bool splats = false,
       bool sums_samples = true);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  size_t pixels() const { return size_t(width_) * height_; }
  cl::Buffer& sum() { return sum_; }
  cl::Buffer& sum_sq() { return sum_sq_; }
  cl::Buffer& ray_counts() { return ray_counts_; }
  bool splats() const { return splats_; }
  bool sums_samples() const { return sums_samples_ && !splats_; }
  cl::Buffer& splat() { return splat_; }  // only with splats
  size_t device_bytes() const {
    return sum_.size() + sum_sq_.size() + ray_counts_.size() + (splats_ ? splat_.size() : 0);
  }

  // Reads the film back.
  FilmSums read() const;
  // Reads the film back and divides by the samples taken.
  FilmResult resolve(uint64_t samples_per_pixel) const { return resolve_film(read(), samples_per_pixel); }

 private:
  uint32_t width_, height_;
  bool splats_;
  bool sums_samples_;
  cl::Buffer sum_, sum_sq_, ray_counts_, splat_;
};

}  // namespace clpt
