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
};

// Construction-time settings some integrators take.
struct IntegratorConfig {
  size_t path_memory_bytes = size_t(256) << 20;  // bdpt: light vertex buffer budget
};

// Names accepted by --integrator, and which of them are implemented.
const std::vector<std::string>& integrator_names();
bool integrator_implemented(const std::string& name);
// Whether it splats (lt, bdpt): its film needs a splat buffer and has no per-pixel variance.
bool integrator_splats(const std::string& name);

// Throws Error(Usage) for an unknown or not yet implemented name.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const cl::Context& ctx,
                                            const SceneBuffers& scene,
                                            const IntegratorConfig& config = {});

}  // namespace clpt
