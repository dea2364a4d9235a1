// A photon map on the device: the photons one PhotonTracer pass stores, sorted so that every
// run builds the same map, and the heap-ordered kd-tree over them (kdtree.h) that
// kernels/spatial/kdtree.cl searches. pm builds a global and a caustic map; ic's records
// read a global map where they gather from photons (--ic-photons).
#pragma once

#include <cstdint>

#include "cl/buffer.h"
#include "integrators/integrator.h"
#include "photon/photon_tracer.h"

namespace clpt {

struct DevicePhotonMap {
  cl::Buffer nodes, photons;
  uint32_t count = 0;
};

// The seed photon maps use: decorrelated from the camera paths that share pixel and path
// indices as sampler keys.
inline uint32_t photon_map_seed(uint32_t seed) { return seed ^ 0x9e3779b9u; }

// No photons: buffers of one element, so the kernels that take a map bind.
DevicePhotonMap empty_photon_map(const cl::Context& ctx);

// Emits `paths` photon paths (seed photon_map_seed(params.seed) + store, the independent
// sampler, params' depth), keeps those `store` (PHOTON_STORE_*) asks for and uploads them
// with their kd-tree; adds its figures to `stats`. paths 0: the empty map. `who` names the
// integrator in errors.
DevicePhotonMap build_photon_map(const cl::Context& ctx, PhotonTracer& tracer,
                                 const dev::RenderParams& params, uint64_t paths, uint32_t store,
                                 const char* who, PhotonStats& stats);

}  // namespace clpt
