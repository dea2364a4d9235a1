// Classic photon mapping (--integrator pm, kernels/integrators/pm.cl): before the first pass
// it emits the global map's photon paths (every photon) and the caustic map's (L S+ D
// photons only), builds a kd-tree over each on the host (host/photon/kdtree.h) and uploads
// trees and photons; every pass then renders like pt, one work-item per pixel, with direct
// light by NEE, caustics from the caustic map and the rest by final gathering. The maps
// depend only on the seed, so passes, progress snapshots and checkpoints behave as pt's.
#pragma once

#include "integrators/integrator.h"
#include "photon/photon_tracer.h"

namespace clpt {

class PhotonMapper final : public Integrator {
 public:
  // global_paths 0: kDefaultGlobalPaths.
  PhotonMapper(const cl::Context& ctx, const SceneBuffers& scene, uint64_t global_paths,
               uint64_t caustic_paths);
  const char* name() const override { return "pm"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  PhotonStats photon_stats() const override { return stats_; }

  static constexpr uint64_t kDefaultGlobalPaths = 200000;

  // The seed photon passes use: decorrelated from the camera paths that share pixel and path
  // indices as sampler keys.
  static uint32_t photon_seed(uint32_t seed) { return seed ^ 0x9e3779b9u; }

 private:
  void launch(const dev::RenderParams& params, Film& film);
  struct Map {
    cl::Buffer nodes, photons;
    uint32_t count = 0;
  };
  Map build_map(const dev::RenderParams& params, uint64_t paths, uint32_t store);
  Map empty_map() const;  // no photons; buffers of one element so the kernel binds

  const cl::Context& ctx_;
  uint64_t global_paths_, caustic_paths_;
  PhotonTracer tracer_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_;
  cl_uint first_arg_ = 0;
  bool built_ = false;
  Map global_, caustic_;
  PhotonStats stats_;
};

}  // namespace clpt
