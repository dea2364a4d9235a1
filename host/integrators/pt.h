// Megakernel path tracer (kernels/integrators/pt.cl).
#pragma once

#include "integrators/integrator.h"

namespace clpt {

class PathTracer final : public Integrator {
 public:
  PathTracer(const cl::Context& ctx, const SceneBuffers& scene);
  const char* name() const override { return "pt"; }
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
