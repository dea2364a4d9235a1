#include "integrators/pt.h"

namespace clpt {

PathTracer::PathTracer(const cl::Context& ctx, const SceneBuffers& scene)
    : ctx_(ctx),
      program_(ctx, "integrators/pt.cl"),
      kernel_(program_, "pt_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  film_arg_ = scene.bind(kernel_, 0);
}

void PathTracer::render_pass(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  kernel_.args(film_arg_, params_, film.sum(), film.sum_sq(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
