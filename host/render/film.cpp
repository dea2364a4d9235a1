#include "render/film.h"

#include <array>
#include <stdexcept>

namespace clpt {

Film::Film(const cl::Context& ctx, uint32_t width, uint32_t height, bool splats, bool sums_samples)
    : width_(width),
      height_(height),
      splats_(splats),
      sums_samples_(sums_samples),
      sum_(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE, nullptr, "film"),
      sum_sq_(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE, nullptr,
              "film variance buffer"),
      ray_counts_(ctx, size_t(width) * height * sizeof(cl_uint), CL_MEM_READ_WRITE, nullptr,
                  "ray counter buffer") {
  sum_.fill_zero();
  sum_sq_.fill_zero();
  ray_counts_.fill_zero();
  if (splats_) {
    splat_ = cl::Buffer(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE,
                        nullptr, "splat film");
    splat_.fill_zero();
  }
}

FilmSums Film::read() const {
  const size_t n = pixels();
  FilmSums f;
  f.width = width_;
  f.height = height_;
  f.splats = splats_;
  f.sums_samples = sums_samples();
  f.sum = sum_.read_vector<std::array<float, 4>>(n);
  f.sum_sq = sum_sq_.read_vector<std::array<float, 4>>(n);
  f.rays = ray_counts_.read_vector<uint32_t>(n);
  if (splats_) f.splat = splat_.read_vector<std::array<float, 4>>(n);
  return f;
}

void FilmSums::add(const FilmSums& o) {
  if (o.width != width || o.height != height || o.splats != splats || o.sum.size() != sum.size())
    throw std::logic_error("films of different sizes or kinds cannot be added");
  for (size_t i = 0; i < sum.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      sum[i][c] += o.sum[i][c];
      sum_sq[i][c] += o.sum_sq[i][c];
      if (splats) splat[i][c] += o.splat[i][c];
    }
  for (size_t i = 0; i < rays.size(); ++i) rays[i] += o.rays[i];
}

std::vector<Cluster::Piece> FilmSums::pieces() const {
  std::vector<Cluster::Piece> p = {{sum.data(), sum.size() * sizeof(sum[0])},
                                   {sum_sq.data(), sum_sq.size() * sizeof(sum_sq[0])},
                                   {rays.data(), rays.size() * sizeof(rays[0])}};
  if (splats) p.push_back({splat.data(), splat.size() * sizeof(splat[0])});
  return p;
}

namespace {
template <typename T>
void add_values(void* to, size_t bytes_to, size_t offset, const void* chunk, size_t bytes) {
  if (offset + bytes > bytes_to || offset % sizeof(T) || bytes % sizeof(T))
    throw std::logic_error("a film chunk outside its array");
  T* dst = reinterpret_cast<T*>(static_cast<char*>(to) + offset);
  const T* src = static_cast<const T*>(chunk);
  for (size_t i = 0; i < bytes / sizeof(T); ++i) dst[i] += src[i];
}
}  // namespace

void FilmSums::add_chunk(size_t piece, size_t offset, const void* chunk, size_t bytes) {
  switch (piece) {
    case 0: return add_values<float>(sum.data(), sum.size() * sizeof(sum[0]), offset, chunk, bytes);
    case 1: return add_values<float>(sum_sq.data(), sum_sq.size() * sizeof(sum_sq[0]), offset, chunk, bytes);
    case 2: return add_values<uint32_t>(rays.data(), rays.size() * sizeof(rays[0]), offset, chunk, bytes);
    case 3: return add_values<float>(splat.data(), splat.size() * sizeof(splat[0]), offset, chunk, bytes);
  }
  throw std::logic_error("no such film piece");
}

FilmResult resolve_film(const FilmSums& f, uint64_t spp) {
  const size_t n = size_t(f.width) * f.height;
  const auto& sum = f.sum;
  const auto& sq = f.sum_sq;
  const auto& rays = f.rays;
  const auto& splat = f.splat;
  const bool splats_ = f.splats;
  FilmResult r;
  r.mean = Image(f.width, f.height);
  r.variance = Image(f.width, f.height);
  r.samples_per_pixel = spp;
  r.variance_available = f.sums_samples;
  for (size_t i = 0; i < n; ++i) {
    if (splats_) {
      // N = spp * pixels light paths; each splat already carries the 1 / A_pixel of the
      // pixel's importance relative to the whole film, so sum / spp is the pixel's estimate
      // (kernels/integrators/lt/light_trace.cl, docs/concepts/light-tracing.md).
      r.dropped_samples += static_cast<uint64_t>(splat[i][3]);
      r.rays += rays[i];
      for (int c = 0; c < 3; ++c)
        r.mean.rgb[i * 3 + c] =
            spp ? static_cast<float>((double(sum[i][c]) + double(splat[i][c])) / double(spp)) : 0.0f;
      continue;
    }
    // Dropped samples count as zero radiance, so the estimate stays over all spp samples.
    r.dropped_samples += static_cast<uint64_t>(sum[i][3]);
    r.rays += rays[i];
    for (int c = 0; c < 3; ++c) {
      const double mean = spp ? double(sum[i][c]) / double(spp) : 0.0;
      const double var = spp > 1 ? (double(sq[i][c]) - double(spp) * mean * mean) / double(spp - 1)
                                 : 0.0;
      r.mean.rgb[i * 3 + c] = static_cast<float>(mean);
      r.variance.rgb[i * 3 + c] = static_cast<float>(var > 0.0 ? var : 0.0);
    }
  }
  return r;
}

}  // namespace clpt
