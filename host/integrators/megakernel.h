// An integrator that is one kernel launched once per pass, with the argument layout
// (scene buffers..., RenderParams, film sum, film sum of squares, ray counts):
// pt and direct (kernels/integrators/pt.cl), ao (kernels/integrators/ao.cl).
#pragma once

#include <vector>

#include "integrators/integrator.h"

namespace clpt {

class MegakernelIntegrator final : public Integrator {
 public:
  // own_params: the bytes of the integrator's own __constant struct (ao's AoParams), bound
  // after RenderParams; empty for none.
  MegakernelIntegrator(const cl::Context& ctx, const SceneBuffers& scene, const char* name,
                       const cl::ProgramSpec& program, const char* kernel_name,
                       const std::vector<unsigned char>& own_params = {});
  const char* name() const override { return name_; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }

 private:
  const cl::Context& ctx_;
  const char* name_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_;
  cl::Buffer own_params_;  // empty (no argument) without
  cl_uint film_arg_ = 0;  // first argument after the scene's
};

}  // namespace clpt
