// Ward's irradiance cache (--integrator ic, kernels/integrators/ic.cl,
// docs/concepts/irradiance-caching.md). The first pass builds the cache on the device:
// placement passes over a coarse-to-fine pixel grid (step 2^k ... 1) find the camera's first
// non-delta vertices that no record covers yet; the host thins each pass's candidates (none
// within another's smallest validity radius), the device computes their records (one
// work-item per hemisphere ray, then one per record), and the host rebuilds the lookup grid
// (ic_grid.h) from the records read back. Every pass then renders samples as pt does, with
// the indirect diffuse light at the first non-delta vertex read from the cache.
#pragma once

#include "integrators/ic_grid.h"
#include "integrators/integrator.h"
#include "shared/ic_types.h"

namespace clpt {

class IrradianceCache final : public Integrator {
 public:
  IrradianceCache(const cl::Context& ctx, const SceneBuffers& scene, const IcConfig& config);
  const char* name() const override { return "ic"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  IcStats ic_stats() const override;

  // The records after the first pass (tests).
  const std::vector<dev::IcRecord>& records() const { return records_; }
  // M and N of M x N hemisphere rays for `rays` asked for: N ~ pi M (Ward's square-ish
  // strata), at least 1 x 1.
  static void strata(uint32_t rays, uint32_t* m, uint32_t* n);

 private:
  void build(const dev::RenderParams& params);
  void place(uint32_t step);
  void launch_render(Film& film);
  void compute_records(size_t first, size_t count);
  void upload_records();  // records_ to the device
  void upload_grid();     // the grid over records_ to the device
  // Binds the cache's four arguments from `first`; returns the next free index.
  cl_uint bind_cache(cl::Kernel& kernel, cl_uint first);

  const cl::Context& ctx_;
  IcConfig config_;
  cl::Program program_;
  cl::Kernel place_kernel_, rays_kernel_, finish_kernel_, render_kernel_;
  cl::Buffer params_, place_params_, ic_params_;
  cl::Buffer records_buf_, starts_, entries_, marks_, lookup_counts_;
  cl::Buffer results_;
  dev::IcParams ic_{};
  std::vector<dev::IcRecord> records_;
  IcGrid grid_;
  bool built_ = false;
  size_t pixels_ = 0;
  uint32_t width_ = 0, height_ = 0;
  cl_uint place_arg_ = 0, rays_arg_ = 0, render_arg_ = 0;
  IcStats stats_;
};

}  // namespace clpt
