#include "integrators/integrator.h"

#include <algorithm>

#include "integrators/bdpt.h"
#include "integrators/light_tracer.h"
#include "integrators/megakernel.h"
#include "integrators/photon_mapper.h"
#include "integrators/sppm.h"
#include "util/error.h"

namespace clpt {

const std::vector<std::string>& integrator_names() {
  static const std::vector<std::string> names = {"pt",   "lt",  "bdpt", "pm",  "sppm",
                                                 "vcm",  "mlt", "ic",   "ao",  "direct"};
  return names;
}

bool integrator_implemented(const std::string& name) {
  return name == "pt" || name == "lt" || name == "bdpt" || name == "pm" || name == "sppm" ||
         name == "direct" || name == "ao";
}

bool integrator_splats(const std::string& name) { return name == "lt" || name == "bdpt"; }

bool integrator_sums_samples(const std::string& name) {
  return !integrator_splats(name) && name != "sppm";
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const cl::Context& ctx,
                                            const SceneBuffers& scene,
                                            const IntegratorConfig& config) {
  const auto& names = integrator_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    throw Error(ExitCode::Usage, "--integrator " + name + ": unknown integrator");
  // `direct` is the path tracer stopped after one bounce (the renderer clamps max depth).
  if (name == "pt" || name == "direct")
    return std::make_unique<MegakernelIntegrator>(ctx, scene, name == "pt" ? "pt" : "direct",
                                                  "integrators/pt.cl", "pt_render");
  if (name == "lt") return std::make_unique<LightTracer>(ctx, scene);
  if (name == "bdpt")
    return std::make_unique<BidirectionalPathTracer>(ctx, scene, config.path_memory_bytes);
  if (name == "pm")
    return std::make_unique<PhotonMapper>(ctx, scene, config.photons, config.caustic_photons);
  if (name == "sppm") return std::make_unique<Sppm>(ctx, scene, config.photons);
  if (name == "ao")
    return std::make_unique<MegakernelIntegrator>(ctx, scene, "ao", "integrators/ao.cl", "ao_render");
  throw Error(ExitCode::Usage,
              "--integrator " + name + ": not implemented yet (available: pt, lt, bdpt, pm, sppm, direct, ao)");
}

}  // namespace clpt
