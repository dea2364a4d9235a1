// Bidirectional path tracing (--integrator bdpt, kernels/integrators/bdpt.cl). Per sample
// index, two kernels over a tile of pixels: bdpt_light traces one light subpath per pixel
// index (splatting the t = 1 strategies, storing connectable vertices), bdpt_camera traces one
// camera subpath per pixel and joins it with the light subpath of the same index. The light
// vertex buffer holds max(max_depth - 1, 1) vertices of 128 bytes per light path of a tile;
// tiles are as large as the memory budget allows (BdptConfig::memory_bytes, --bdpt-memory).
// Like lt, its film has splats: no per-pixel variance, sums not bit-reproducible.
#pragma once

#include <cstddef>

#include "integrators/integrator.h"

namespace clpt {

class BidirectionalPathTracer final : public Integrator {
 public:
  BidirectionalPathTracer(const cl::Context& ctx, const SceneBuffers& scene, const BdptConfig& config);
  const char* name() const override { return "bdpt"; }
  // The film must have been made with splats (Film(..., true)).
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  uint64_t connections() const override;

  // Light vertices stored per light path for a maximum depth, and the pixels per tile a
  // budget allows (at least one work-group's worth is not promised: at least 1).
  static uint32_t vertex_capacity(uint32_t max_depth);
  static size_t tile_paths(size_t budget_bytes, uint32_t capacity, size_t pixels);

 private:
  // Uploads the pass's parameters (and BdptParams with the light vertex capacity its depth
  // needs); buffers sized for the film.
  void prepare(const dev::RenderParams& params, Film& film);
  void ensure_buffers(uint32_t capacity, size_t tile);

  const cl::Context& ctx_;
  BdptConfig config_;
  cl::Program program_;
  cl::Kernel light_kernel_, camera_kernel_;
  cl::Buffer params_, bdpt_params_;  // RenderParams, BdptParams
  cl::Buffer vertices_, vertex_counts_;
  cl::Buffer connection_counts_;
  cl::Buffer pool_count_;  // light vertex caching: vertices appended to the tile's cache  // per pixel index, allocated with the first pass
  size_t pixels_ = 0;
  uint32_t capacity_ = 0;
  size_t tile_ = 0;
  cl_uint light_arg_ = 0, camera_arg_ = 0;  // first argument after the scene's
};

}  // namespace clpt
