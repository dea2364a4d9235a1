// Light after exactly one bounce (--integrator indirect1, kernels/integrators/indirect1.cl,
// docs/concepts/indirect-generators.md): at the camera's first hit x, the light that arrives
// from surface points y lit directly by a light, found by one of the lecture's three
// generators (--indirect receiver|source|surface). One kernel per pass as pt; surface
// sampling reads a distribution over the scene's triangles in proportion to their areas,
// built once from the device's own triangle areas.
#pragma once

#include "integrators/integrator.h"
#include "shared/indirect_types.h"

namespace clpt {

class OneBounceIndirect final : public Integrator {
 public:
  OneBounceIndirect(const cl::Context& ctx, const SceneBuffers& scene, uint32_t generator);
  const char* name() const override { return "indirect1"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }

  // The CDF (areas.size() + 1 values, first 0, last exactly 1) of picking each triangle in
  // proportion to its area, summed in double; *total gets the sum. All zero areas (or none):
  // an empty CDF.
  static std::vector<float> area_cdf(const std::vector<float>& areas, double* total);

 private:
  const cl::Context& ctx_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_, indirect_params_, cdf_;
  cl_uint film_arg_ = 0;
};

}  // namespace clpt
