#include "integrators/light_tracer.h"

#include "cl/programs.h"
#include "util/error.h"

namespace clpt {

LightTracer::LightTracer(const cl::Context& ctx, const SceneBuffers& scene)
    : ctx_(ctx),
      program_(ctx, programs::kLt),
      kernel_(program_, "lt_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  film_arg_ = scene.bind(kernel_, 0);
}

void LightTracer::warm_up(const dev::RenderParams& params, Film& film) {
  render_pass(without_samples(params), film);
}

void LightTracer::render_pass(const dev::RenderParams& params, Film& film) {
  if (!film.splats()) throw Error(ExitCode::Usage, "the light tracer needs a film with splats");
  params_.write(&params, sizeof(params));
  kernel_.args(film_arg_, params_, film.splat(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
