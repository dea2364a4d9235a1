// Classic photon mapping (--integrator pm, kernels/integrators/pm.cl): before the first pass
// it emits the global map's photon paths (every photon) and the caustic map's (L S+ D
// photons only), builds a kd-tree over each on the host (photon_map.h) and uploads trees and
// photons; every pass then renders like pt, one work-item per pixel, with direct light by
// NEE, caustics from the caustic map and the rest by final gathering. With
// --final-gather-cache the final gather's diffuse part is read from an irradiance cache
// (ic_records.h) whose records gather from the global map, built after the maps (Jensen 2001,
// ch. 9). The maps and the cache depend only on the seed, so passes, progress snapshots and
// checkpoints behave as pt's.
#pragma once

#include <memory>

#include "integrators/ic_records.h"
#include "integrators/integrator.h"
#include "integrators/photon_map.h"
#include "photon/photon_tracer.h"

namespace clpt {

class PhotonMapper final : public Integrator {
 public:
  // cache: the irradiance cache's settings (with pm.final_gather_cache), null for none.
  PhotonMapper(const cl::Context& ctx, const SceneBuffers& scene, const PmConfig& pm,
               const SceneScale& scale, const IcConfig* cache = nullptr);
  const char* name() const override { return "pm"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  PhotonStats photon_stats() const override { return stats_; }
  IcStats ic_stats() const override { return cache_ ? cache_->stats() : IcStats{}; }

  static constexpr uint64_t kDefaultGlobalPaths = 200000;

  // The seed photon passes use (photon_map.h).
  static uint32_t photon_seed(uint32_t seed) { return photon_map_seed(seed); }

 private:
  void launch(const dev::RenderParams& params, Film& film);

  const cl::Context& ctx_;
  uint64_t global_paths_, caustic_paths_;
  PhotonTracer tracer_;
  std::unique_ptr<IcRecords> cache_;
  std::unique_ptr<IcNoCache> no_cache_;  // what the kernel's cache arguments bind without one
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_, pm_params_;  // RenderParams, PmParams
  cl_uint first_arg_ = 0;
  bool built_ = false;
  DevicePhotonMap global_, caustic_;
  PhotonStats stats_;
};

}  // namespace clpt
