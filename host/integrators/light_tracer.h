// Light tracing (--integrator lt, kernels/integrators/lt.cl): light paths that connect every
// vertex to the camera and splat into the film's splat buffer. A pass traces
// samples * width * height light paths (one work-item per "virtual pixel", `samples` paths
// each), so --spp keeps meaning paths per pixel on average. Its film has no per-pixel
// variance, and its sums are not bit-reproducible (float atomics in no fixed order).
#pragma once

#include "integrators/integrator.h"

namespace clpt {

class LightTracer final : public Integrator {
 public:
  LightTracer(const cl::Context& ctx, const SceneBuffers& scene);
  const char* name() const override { return "lt"; }
  // The film must have been made with splats (Film(..., true)).
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }

 private:
  const cl::Context& ctx_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_;
  cl_uint film_arg_ = 0;  // first argument after the scene's
};

}  // namespace clpt
