#include "integrators/bdpt.h"

#include <algorithm>

#include "cl/programs.h"
#include "shared/bdpt_types.h"
#include "util/error.h"

namespace clpt {

static_assert(sizeof(dev::PathVertex) == 192, "PathVertex: 192 bytes, a multiple of 16");

BidirectionalPathTracer::BidirectionalPathTracer(const cl::Context& ctx, const SceneBuffers& scene,
                                                 const BdptConfig& config)
    : ctx_(ctx),
      config_(config),
      program_(ctx, programs::kBdpt),
      light_kernel_(program_, "bdpt_light"),
      camera_kernel_(program_, "bdpt_camera"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      bdpt_params_(ctx, sizeof(dev::BdptParams), CL_MEM_READ_ONLY, nullptr, "bdpt parameters"),
      pool_count_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "BDPT light vertex cache count") {
  light_arg_ = scene.bind(light_kernel_, 0);
  camera_arg_ = scene.bind(camera_kernel_, 0);
}

uint32_t BidirectionalPathTracer::vertex_capacity(uint32_t max_depth) {
  return std::max<uint32_t>(max_depth, 2u) - 1u;
}

size_t BidirectionalPathTracer::tile_paths(size_t budget_bytes, uint32_t capacity, size_t pixels) {
  const size_t per_path = size_t(capacity) * sizeof(dev::PathVertex) + sizeof(uint32_t);
  return std::clamp<size_t>(budget_bytes / per_path, 1, std::max<size_t>(pixels, 1));
}

void BidirectionalPathTracer::ensure_buffers(uint32_t capacity, size_t tile) {
  if (capacity == capacity_ && tile == tile_) return;
  vertices_ = cl::Buffer(ctx_, size_t(capacity) * tile * sizeof(dev::PathVertex), CL_MEM_READ_WRITE,
                         nullptr, "BDPT light vertices");
  vertex_counts_ = cl::Buffer(ctx_, tile * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                              "BDPT light vertex counts");
  capacity_ = capacity;
  tile_ = tile;
}

void BidirectionalPathTracer::prepare(const dev::RenderParams& params, Film& film) {
  if (!film.splats()) throw Error(ExitCode::Usage, "bdpt needs a film with splats");
  dev::BdptParams b{};
  b.strategy_s = config_.strategy_s;
  b.strategy_t = config_.strategy_t;
  b.unweighted = config_.unweighted ? 1u : 0u;
  b.light_vertex_capacity = vertex_capacity(params.max_depth);
  b.lvc = config_.lvc;
  const size_t pixels = film.pixels();
  if (pixels_ != pixels) {
    connection_counts_ = cl::Buffer(ctx_, pixels * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                                    "BDPT connection counts");
    connection_counts_.fill_zero();
    pixels_ = pixels;
  }
  ensure_buffers(b.light_vertex_capacity,
                 tile_paths(config_.memory_bytes, b.light_vertex_capacity, pixels));
  params_.write(&params, sizeof(params));
  bdpt_params_.write(&b, sizeof(b));
}

void BidirectionalPathTracer::warm_up(const dev::RenderParams& params, Film& film) {
  prepare(params, film);
  // Both kernels over no paths.
  const uint32_t none = 0;
  light_kernel_.args(light_arg_, params_, bdpt_params_, none, none, none, vertices_, vertex_counts_,
                     pool_count_, film.splat(), film.ray_counts(), connection_counts_);
  light_kernel_.launch(ctx_, 1);
  camera_kernel_.args(camera_arg_, params_, bdpt_params_, none, none, none, vertices_, vertex_counts_,
                      pool_count_, film.sum(), film.sum_sq(), film.splat(), film.ray_counts(),
                      connection_counts_);
  camera_kernel_.launch(ctx_, 1);
}

void BidirectionalPathTracer::render_pass(const dev::RenderParams& params, Film& film) {
  prepare(params, film);
  const size_t pixels = film.pixels();
  for (uint32_t i = 0; i < params.samples_per_pass; ++i) {
    const uint32_t sample = params.sample_offset + i;
    for (size_t offset = 0; offset < pixels; offset += tile_) {
      const auto count = static_cast<uint32_t>(std::min(tile_, pixels - offset));
      const auto first = static_cast<uint32_t>(offset);
      if (config_.lvc) pool_count_.fill_zero();
      light_kernel_.args(light_arg_, params_, bdpt_params_, sample, first, count, vertices_, vertex_counts_,
                         pool_count_, film.splat(), film.ray_counts(), connection_counts_);
      light_kernel_.launch(ctx_, count);
      camera_kernel_.args(camera_arg_, params_, bdpt_params_, sample, first, count, vertices_, vertex_counts_,
                          pool_count_, film.sum(), film.sum_sq(), film.splat(), film.ray_counts(),
                          connection_counts_);
      camera_kernel_.launch(ctx_, count);
    }
  }
}

uint64_t BidirectionalPathTracer::connections() const {
  if (!pixels_) return 0;
  uint64_t n = 0;
  for (uint32_t c : connection_counts_.read_vector<uint32_t>(pixels_)) n += c;
  return n;
}

}  // namespace clpt
