// Photon emission on the device (kernels/integrators/photon.cl): traces photon paths from
// the lights and stores their photons, for the photon maps of --integrator pm and the
// passes of sppm. Photons are 64 bytes (dev::Photon, kernels/shared/photon_types.h).
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
  // params.sample_offset, into `photons` (room for `capacity`); `store` is a mask of
  // PHOTON_STORE_* (0: every photon). Returns how many photons the paths made: more than
  // capacity means only `capacity` of them were kept, which ones undefined (emit again into
  // a larger buffer: the same params give the same photons). Blocks until done.
  uint64_t emit(const dev::RenderParams& params, uint64_t paths, uint32_t store,
                cl::Buffer& photons, size_t capacity);

  // emit() into a buffer of `capacity` read back to the host.
  PhotonSet trace(const dev::RenderParams& params, uint64_t paths, uint32_t store,
                  size_t capacity);

  // Launches the kernel as emit() would for `paths` paths, but with none to trace, so a
  // driver that compiles at the first launch does it now rather than in the first timed
  // pass. The launch's size matters: PoCL compiles again for a much larger grid (a warm-up
  // over 4 096 work-items left the first 200 000-path launch 4x slower, one over 65 536 did
  // not; docs/BENCHMARKS.md, session 5).
  void warm_up(uint64_t paths);

  // Photon paths' rays (closest hits) traced so far.
  uint64_t rays() const { return rays_; }

 private:
  // Paths per launch at most, so the 32-bit counters cannot wrap within one (a path
  // stores at most max_depth <= 1024 photons and traces as many rays).
  static constexpr uint64_t kChunk = uint64_t(1) << 20;

  const cl::Context& ctx_;
  cl::Program program_;
  cl::Kernel kernel_;
  cl::Buffer params_, count_, ray_count_;
  cl_uint first_arg_ = 0;
  uint64_t rays_ = 0;
};

}  // namespace clpt
