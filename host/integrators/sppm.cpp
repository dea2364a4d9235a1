#include "integrators/sppm.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cl/programs.h"
#include "integrators/photon_mapper.h"
#include "util/error.h"
#include "util/timer.h"

namespace clpt {

static_assert(sizeof(dev::SppmPixel) == 32, "SppmPixel should stay 32 bytes");

Sppm::Sppm(const cl::Context& ctx, const SceneBuffers& scene, const SppmConfig& config,
           const SceneScale& scale)
    : ctx_(ctx),
      paths_per_pass_(config.photons),
      initial_radius_(config.radius > 0.0f ? config.radius : default_merge_radius(scale)),
      alpha_(config.alpha),
      tracer_(ctx, scene),
      program_(ctx, programs::kSppm),
      insert_kernel_(program_, "sppm_grid_insert"),
      pass_kernel_(program_, "sppm_pass"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      max_radius_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "SPPM largest radius") {
  pass_arg_ = scene.bind(pass_kernel_, 0);
}

void Sppm::start(size_t pixels) {
  std::vector<dev::SppmPixel> init(pixels);
  for (dev::SppmPixel& px : init) {
    std::memset(&px, 0, sizeof(px));
    px.radius = initial_radius_;
  }
  pixels_ = cl::Buffer::from_vector(ctx_, init, CL_MEM_READ_WRITE, "SPPM pixel statistics");
  pixel_count_ = pixels;
  cell_ = initial_radius_;
  next_sample_ = 0;
}

void Sppm::prepare(const dev::RenderParams& params, Film& film) {
  if (film.sums_samples()) throw Error(ExitCode::Usage, "sppm needs a film without sample sums");
  if (pixel_count_ != film.pixels()) start(film.pixels());
  if (paths_per_pass_ == 0) paths_per_pass_ = film.pixels();
  params_.write(&params, sizeof(params));
}

void Sppm::warm_up(const dev::RenderParams& params, Film& film) {
  prepare(params, film);
  // Every kernel over nothing, over grids the size of a pass's (PoCL compiles
  // again for a much larger grid; PhotonTracer::warm_up); the grid insertion's is taken
  // as the pass's path count.
  tracer_.warm_up(paths_per_pass_);
  cl::Buffer none(ctx_, sizeof(dev::Photon));
  cl::Buffer heads(ctx_, sizeof(uint32_t)), next(ctx_, sizeof(uint32_t));
  const uint32_t zero = 0;
  const float one = 1.0f;
  insert_kernel_.args(0, none, zero, one, zero, heads, next);
  insert_kernel_.launch(ctx_, paths_per_pass_);
  pass_kernel_.args(pass_arg_, params_, alpha_, zero, zero, none, heads, next, one, zero, pixels_,
                    film.sum(), film.ray_counts(), max_radius_);
  pass_kernel_.launch(ctx_, film.pixels());
}

void Sppm::render_pass(const dev::RenderParams& params, Film& film) {
  prepare(params, film);
  if (params.sample_offset != next_sample_)
    throw Error(ExitCode::Usage, "sppm passes must come in order (expected sample " +
                                     std::to_string(next_sample_) + ", got " +
                                     std::to_string(params.sample_offset) + ")");
  for (uint32_t i = 0; i < params.samples_per_pass; ++i) one_pass(params, params.sample_offset + i, film);
  next_sample_ = params.sample_offset + params.samples_per_pass;
}

void Sppm::one_pass(const dev::RenderParams& params, uint32_t sample, Film& film) {
  // The pass's photons: the same sampler key scheme as pm's maps, one sample index per pass.
  dev::RenderParams pp = params;
  pp.seed = PhotonMapper::photon_seed(params.seed);
  pp.sampler = dev::SAMPLER_INDEPENDENT;
  pp.sample_offset = sample;
  if (capacity_ == 0) {
    capacity_ = static_cast<size_t>(paths_per_pass_) * 2;
    photons_ = cl::Buffer(ctx_, capacity_ * sizeof(dev::Photon), CL_MEM_READ_WRITE, nullptr,
                          "SPPM photons");
  }
  auto t0 = Clock::now();
  uint64_t made = tracer_.emit(pp, paths_per_pass_, PHOTON_STORE_SKIP_DIRECT, photons_, capacity_);
  if (made > capacity_) {
    // Grow with a margin and emit again: the same parameters give the same photons.
    capacity_ = static_cast<size_t>(made + made / 4);
    photons_ = cl::Buffer(ctx_, capacity_ * sizeof(dev::Photon), CL_MEM_READ_WRITE, nullptr,
                          "SPPM photons");
    made = tracer_.emit(pp, paths_per_pass_, PHOTON_STORE_SKIP_DIRECT, photons_, capacity_);
  }
  stats_.emit_seconds += seconds_since(t0);
  stats_.paths += paths_per_pass_;
  stats_.stored += made;
  const auto count = static_cast<uint32_t>(made);

  // The hash table: a power of two at least twice the photon buffer, sized with it.
  size_t buckets = 1024;
  while (buckets < 2 * capacity_) buckets *= 2;
  if (bucket_mask_ + size_t(1) != buckets) {
    heads_ = cl::Buffer(ctx_, buckets * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "SPPM grid");
    next_ = cl::Buffer(ctx_, capacity_ * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                       "SPPM grid links");
    bucket_mask_ = static_cast<uint32_t>(buckets - 1);
  } else if (next_.size() < capacity_ * sizeof(uint32_t)) {
    next_ = cl::Buffer(ctx_, capacity_ * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                       "SPPM grid links");
  }
  t0 = Clock::now();
  const float inv_cell = 1.0f / cell_;
  heads_.fill_zero();
  insert_kernel_.args(0, photons_, count, inv_cell, bucket_mask_, heads_, next_);
  if (count) insert_kernel_.launch(ctx_, count);
  ctx_.finish();
  stats_.build_seconds += seconds_since(t0);
  ++stats_.builds;

  max_radius_.fill_zero();
  const auto pixels = static_cast<uint32_t>(film.pixels());
  pass_kernel_.args(pass_arg_, params_, alpha_, pixels, sample, photons_, heads_, next_, inv_cell, bucket_mask_,
                    pixels_, film.sum(), film.ray_counts(), max_radius_);
  pass_kernel_.launch(ctx_, film.pixels());
  uint32_t bits = max_radius_.read_vector<uint32_t>(1)[0];
  float r;
  std::memcpy(&r, &bits, sizeof(r));
  if (r > 0.0f && std::isfinite(r)) cell_ = r;
  stats_.rays = tracer_.rays();
  stats_.device_bytes = photons_.size() + heads_.size() + next_.size() + pixels_.size();
}

PhotonStats Sppm::photon_stats() const { return stats_; }

}  // namespace clpt
