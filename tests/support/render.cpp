#include "support/render.h"

#include "support/device.h"

namespace clpt::test {

RenderSettings render_settings(const std::string& integrator, uint64_t spp, uint32_t size) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.integrator = integrator;
  return s;
}

FilmResult render(const Scene& scene, RenderSettings settings, uint32_t seed) {
  settings.seed = seed;
  return Renderer(device_context(), scene, settings).render().film;
}

}  // namespace clpt::test
