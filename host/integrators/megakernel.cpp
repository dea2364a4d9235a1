#include "integrators/megakernel.h"

namespace clpt {

MegakernelIntegrator::MegakernelIntegrator(const cl::Context& ctx, const SceneBuffers& scene,
                                           const char* name, const cl::ProgramSpec& program,
                                           const char* kernel_name,
                                           const std::vector<unsigned char>& own_params)
    : ctx_(ctx),
      name_(name),
      program_(ctx, program),
      kernel_(program_, kernel_name),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  if (!own_params.empty())
    own_params_ = cl::Buffer(ctx, own_params.size(), CL_MEM_READ_ONLY, own_params.data(),
                             "integrator parameters");
  film_arg_ = scene.bind(kernel_, 0);
}

void MegakernelIntegrator::warm_up(const dev::RenderParams& params, Film& film) {
  render_pass(without_samples(params), film);
}

void MegakernelIntegrator::render_pass(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  const cl_uint next = own_params_.size() ? kernel_.args(film_arg_, params_, own_params_)
                                           : kernel_.args(film_arg_, params_);
  kernel_.args(next, film.sum(), film.sum_sq(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
