#include "integrators/irradiance_cache.h"

#include "util/timer.h"

namespace clpt {

IrradianceCache::IrradianceCache(const cl::Context& ctx, const SceneBuffers& scene,
                                 const IcConfig& config, const dev::PhotonLookup& photons)
    : ctx_(ctx),
      config_(config),
      cache_(ctx, scene, config, config.photons ? dev::IC_GATHER_PHOTONS : dev::IC_GATHER_PATHS,
             photons),
      tracer_(config.photons ? std::make_unique<PhotonTracer>(ctx, scene) : nullptr),
      render_kernel_(cache_.program(), "ic_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  render_arg_ = scene.bind(render_kernel_, 0);
}

void IrradianceCache::warm_up(const dev::RenderParams& params, Film& film) {
  if (tracer_) tracer_->warm_up(config_.photons);
  cache_.warm_up(params, film.pixels());
  const dev::RenderParams none = without_samples(params);
  params_.write(&none, sizeof(none));
  launch_render(film);
}

void IrradianceCache::launch_render(Film& film) {
  const cl_uint next = cache_.bind_image(render_kernel_, render_kernel_.args(render_arg_, params_));
  render_kernel_.args(next, film.sum(), film.sum_sq(), film.ray_counts());
  render_kernel_.launch(ctx_, film.pixels());
}

void IrradianceCache::render_pass(const dev::RenderParams& params, Film& film) {
  if (!cache_.built()) {
    const auto started = Clock::now();
    if (tracer_) {  // path-traced records read no map
      global_ = build_photon_map(ctx_, *tracer_, params, config_.photons, 0u, "ic", photon_stats_);
      photon_stats_.rays = tracer_->rays();
    }
    cache_.build(params, global_, started, stop_flag());
  }
  params_.write(&params, sizeof(params));
  cache_.write_params();
  launch_render(film);
}

}  // namespace clpt
