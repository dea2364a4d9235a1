// Ward's irradiance cache as an integrator (--integrator ic, kernels/integrators/ic.cl,
// docs/concepts/irradiance-caching.md). The first pass builds the cache (ic_records.h), its
// records' rays path traced or, with --ic-photons, reading a global photon map built first;
// every pass then renders samples as pt does, with the indirect diffuse light at the first
// non-delta vertex read from the cache.
#pragma once

#include <memory>

#include "integrators/ic_records.h"
#include "integrators/integrator.h"
#include "integrators/photon_map.h"
#include "photon/photon_tracer.h"

namespace clpt {

class IrradianceCache final : public Integrator {
 public:
  // photons: how records read the global map with --ic-photons (photon_lookup).
  IrradianceCache(const cl::Context& ctx, const SceneBuffers& scene, const IcConfig& config,
                  const dev::PhotonLookup& photons);
  const char* name() const override { return "ic"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return cache_.program().build_info(); }
  IcStats ic_stats() const override { return cache_.stats(); }
  PhotonStats photon_stats() const override { return photon_stats_; }

  // The records after the first pass (tests).
  const std::vector<dev::IcRecord>& records() const { return cache_.records(); }
  static void strata(uint32_t rays, uint32_t* m, uint32_t* n) { IcRecords::strata(rays, m, n); }

 private:
  void launch_render(Film& film);

  const cl::Context& ctx_;
  IcConfig config_;
  IcRecords cache_;
  std::unique_ptr<PhotonTracer> tracer_;  // --ic-photons only
  cl::Kernel render_kernel_;
  cl::Buffer params_;
  cl_uint render_arg_ = 0;
  DevicePhotonMap global_;  // --ic-photons: what the records read
  PhotonStats photon_stats_;
};

}  // namespace clpt
