#include "integrators/indirect1.h"

#include <cmath>

#include "cl/programs.h"

namespace clpt {

std::vector<float> OneBounceIndirect::area_cdf(const std::vector<float>& areas, double* total) {
  double sum = 0.0;
  for (float a : areas)
    if (a > 0.0f && std::isfinite(a)) sum += a;
  *total = sum;
  if (!(sum > 0.0)) return {};
  std::vector<float> cdf(areas.size() + 1);
  double run = 0.0;
  cdf[0] = 0.0f;
  for (size_t i = 0; i < areas.size(); ++i) {
    if (areas[i] > 0.0f && std::isfinite(areas[i])) run += areas[i];
    cdf[i + 1] = static_cast<float>(run / sum);
  }
  cdf.back() = 1.0f;
  return cdf;
}

OneBounceIndirect::OneBounceIndirect(const cl::Context& ctx, const SceneBuffers& scene,
                                     uint32_t generator)
    : ctx_(ctx),
      program_(ctx, programs::kIndirect1),
      kernel_(program_, "indirect1_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      indirect_params_(ctx, sizeof(dev::IndirectParams), CL_MEM_READ_ONLY, nullptr,
                       "indirect1 parameters") {
  dev::IndirectParams ip{};
  ip.generator = generator;
  std::vector<float> cdf;
  if (generator == dev::INDIRECT_SURFACE && scene.num_triangles() > 0) {
    const uint32_t n = scene.num_triangles();
    cl::Kernel areas_kernel(program_, "indirect1_areas");
    cl::Buffer areas(ctx, size_t(n) * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                     "triangle areas");
    const cl_uint next = scene.bind(areas_kernel, 0);
    areas_kernel.args(next, n, areas);
    areas_kernel.launch(ctx, n);
    double total = 0.0;
    cdf = area_cdf(areas.read_vector<float>(n), &total);
    if (!cdf.empty()) {
      ip.triangles = n;
      ip.total_area = static_cast<float>(total);
    }
  }
  if (cdf.empty()) cdf.assign(2, 0.0f);  // a valid buffer that no kernel reads (triangles 0)
  cdf_ = cl::Buffer::from_vector(ctx, cdf, CL_MEM_READ_ONLY, "surface area distribution");
  indirect_params_.write(&ip, sizeof(ip));
  film_arg_ = scene.bind(kernel_, 0);
}

void OneBounceIndirect::warm_up(const dev::RenderParams& params, Film& film) {
  render_pass(without_samples(params), film);
}

void OneBounceIndirect::render_pass(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  kernel_.args(film_arg_, params_, indirect_params_, cdf_, film.sum(), film.sum_sq(),
               film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
