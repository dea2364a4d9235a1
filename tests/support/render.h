// One render on the test device, for tests that compare renders of scenes built in code.
#pragma once

#include <cstdint>
#include <string>

#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt::test {

// RenderSettings for `integrator` at size x size pixels and `spp` samples per pixel; every
// other setting its default.
RenderSettings render_settings(const std::string& integrator, uint64_t spp, uint32_t size);

// `scene` rendered on device_context() with `settings` and `seed`.
FilmResult render(const Scene& scene, RenderSettings settings, uint32_t seed);

}  // namespace clpt::test
