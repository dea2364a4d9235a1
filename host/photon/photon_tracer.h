// Photon emission on the device (kernels/integrators/photon.cl): traces photon paths from
// the lights and returns the photons they stored, for the photon maps of --integrator pm
// and sppm (issue 7). Photons are 64 bytes (dev::Photon, kernels/shared/photon_types.h).
#pragma once

#include <cstdint>
#include <vector>

#include "cl/program.h"
#include "render/scene_buffers.h"
#include "shared/photon_types.h"
#include "shared/render_types.h"

namespace clpt {

struct PhotonSet {
  std::vector<dev::Photon> photons;
  uint64_t paths = 0;     // photon paths emitted: each photon's power is divided by this
  uint64_t rays = 0;
  uint64_t dropped = 0;   // photons that did not fit the capacity (0 unless it was too small)
};

class PhotonTracer {
 public:
  PhotonTracer(const cl::Context& ctx, const SceneBuffers& scene);

  // Emits `paths` photon paths with params' seed, sampler and max depth, the pass chosen by
  // params.sample_offset, and keeps at most `capacity` photons (all of them when
  // caustic_only is false; only L S+ D photons when true).
  PhotonSet trace(const dev::RenderParams& params, uint64_t paths, bool caustic_only,
                  size_t capacity);

 private:
  const cl::Context& ctx_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_;
  cl_uint first_arg_ = 0;
};

}  // namespace clpt
