// An integrator owns its kernels and renders in passes: each pass adds
// `samples` samples per pixel, starting at sample index `first_sample`, to the film.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cl/program.h"
#include "render/film.h"
#include "render/scene_buffers.h"
#include "shared/render_types.h"

namespace clpt {

// Photon figures of pm and sppm for --stats (zero for the other integrators).
struct PhotonStats {
  uint64_t paths = 0;             // photon paths emitted (all maps, all passes)
  uint64_t stored = 0;            // photons stored
  uint64_t rays = 0;              // rays the photon paths traced
  double emit_seconds = 0.0;      // photon tracing, device
  double build_seconds = 0.0;     // pm: kd-tree builds (host); sppm: hashed grid builds (device)
  uint64_t builds = 0;            // pm: maps built; sppm: grids built (one per pass)
  size_t device_bytes = 0;        // photon, tree and grid buffers on the device at the end
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual const char* name() const = 0;
  // Enqueues one pass; it completes by the next blocking call on the queue (film read, finish).
  virtual void render_pass(const dev::RenderParams& params, Film& film) = 0;
  // How its program was obtained (cache or build) and how long that took.
  virtual const cl::BuildInfo& build_info() const = 0;
  // Shadow rays of connection strategies so far (bdpt); 0 for integrators without them.
  virtual uint64_t connections() const { return 0; }
  virtual PhotonStats photon_stats() const { return {}; }
};

// Construction-time settings some integrators take.
struct IntegratorConfig {
  size_t path_memory_bytes = size_t(256) << 20;  // bdpt: light vertex buffer budget
  uint64_t photons = 0;          // pm: global map paths; sppm: paths per pass (0: pixels)
  uint64_t caustic_photons = 0;  // pm: caustic map paths
};

// Names accepted by --integrator, and which of them are implemented.
const std::vector<std::string>& integrator_names();
bool integrator_implemented(const std::string& name);
// Whether it splats (lt, bdpt): its film needs a splat buffer.
bool integrator_splats(const std::string& name);
// Whether its film holds sums of independent samples per pixel, so it has a per-pixel
// variance and can be checkpointed: not lt and bdpt (splats), not sppm (its pixels are
// progressive estimates with state of their own).
bool integrator_sums_samples(const std::string& name);

// Throws Error(Usage) for an unknown or not yet implemented name.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const cl::Context& ctx,
                                            const SceneBuffers& scene,
                                            const IntegratorConfig& config = {});

}  // namespace clpt
