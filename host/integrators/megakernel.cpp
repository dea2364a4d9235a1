#include "integrators/megakernel.h"

namespace clpt {

MegakernelIntegrator::MegakernelIntegrator(const cl::Context& ctx, const SceneBuffers& scene,
                                           const char* name, const cl::ProgramSpec& program,
                                           const char* kernel_name)
    : ctx_(ctx),
      name_(name),
      program_(ctx, program),
      kernel_(program_, kernel_name),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  film_arg_ = scene.bind(kernel_, 0);
}

void MegakernelIntegrator::warm_up(const dev::RenderParams& params, Film& film) {
  render_pass(without_samples(params), film);
}

void MegakernelIntegrator::render_pass(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  kernel_.args(film_arg_, params_, film.sum(), film.sum_sq(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
