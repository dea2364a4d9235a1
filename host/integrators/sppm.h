// Stochastic progressive photon mapping (--integrator sppm, kernels/integrators/sppm.cl). A
// pass per sample index: emit the pass's photon paths into a device buffer, hash the photons
// into a grid on the device (one atomic exchange per photon), then one work-item per pixel
// finds its visible point, gathers the photons within its radius and updates its statistics
// (dev::SppmPixel), writing its estimate times the passes into the film's sum. The grid's
// cell side is the largest pixel radius of the previous pass (radii only shrink), so a
// gather visits at most 3 cells per axis.
#pragma once

#include "integrators/integrator.h"
#include "photon/photon_tracer.h"

namespace clpt {

class Sppm final : public Integrator {
 public:
  // config.photons 0: one photon path per pixel; config.radius 0: default_merge_radius.
  Sppm(const cl::Context& ctx, const SceneBuffers& scene, const SppmConfig& config,
       const SceneScale& scale);
  const char* name() const override { return "sppm"; }
  // Passes must come in order from sample index 0 (the statistics are progressive).
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  PhotonStats photon_stats() const override;

 private:
  // Pixel statistics for the film (started on first use), parameters uploaded.
  void prepare(const dev::RenderParams& params, Film& film);
  void start(size_t pixels);
  void one_pass(const dev::RenderParams& params, uint32_t sample, Film& film);

  const cl::Context& ctx_;
  uint64_t paths_per_pass_;
  float initial_radius_;  // every pixel's first radius
  float alpha_;           // the kernel's alpha argument
  PhotonTracer tracer_;
  cl::Program program_;
  cl::Kernel insert_kernel_, pass_kernel_;
  cl::Buffer params_;
  cl::Buffer pixels_, max_radius_;
  cl::Buffer photons_, next_, heads_;
  size_t capacity_ = 0;       // photons the photon buffer holds
  uint32_t bucket_mask_ = 0;  // hash table size - 1
  size_t pixel_count_ = 0;
  uint32_t next_sample_ = 0;  // the sample index the next pass must have
  float cell_ = 0.0f;         // grid cell side for the next pass
  cl_uint pass_arg_ = 0;
  PhotonStats stats_;
};

}  // namespace clpt
