#include "integrators/photon_mapper.h"

#include "cl/programs.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

PhotonMapper::PhotonMapper(const cl::Context& ctx, const SceneBuffers& scene, const PmConfig& pm,
                           const SceneScale& scale, const IcConfig* cache)
    : ctx_(ctx),
      global_paths_(pm.photons ? pm.photons : kDefaultGlobalPaths),
      caustic_paths_(pm.caustic_photons),
      tracer_(ctx, scene),
      cache_(cache ? std::make_unique<IcRecords>(ctx, scene, *cache,
                                                 dev::IC_GATHER_PHOTONS_NO_CAUSTICS,
                                                 photon_lookup(pm, scale))
                   : nullptr),
      no_cache_(cache ? nullptr : std::make_unique<IcNoCache>(ctx)),
      program_(ctx, programs::kPm),
      kernel_(program_, "pm_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  dev::PmParams own{};
  own.lookup = photon_lookup(pm, scale);
  own.final_gather = pm.final_gather;
  pm_params_ = cl::Buffer::from_vector(ctx, std::vector<dev::PmParams>{own}, CL_MEM_READ_ONLY,
                                       "pm parameters");
  first_arg_ = scene.bind(kernel_, 0);
  // Empty maps until the first pass builds them (the warm-up launch reads none).
  global_ = empty_photon_map(ctx);
  caustic_ = empty_photon_map(ctx);
}

void PhotonMapper::warm_up(const dev::RenderParams& params, Film& film) {
  tracer_.warm_up(global_paths_);
  tracer_.warm_up(caustic_paths_);
  if (cache_) cache_->warm_up(params, film.pixels());
  launch(without_samples(params), film);  // reads no map
}

void PhotonMapper::render_pass(const dev::RenderParams& params, Film& film) {
  if (!built_) {
    const auto started = Clock::now();
    global_ = build_photon_map(ctx_, tracer_, params, global_paths_, 0u, "pm", stats_);
    caustic_ = build_photon_map(ctx_, tracer_, params, caustic_paths_, PHOTON_STORE_CAUSTIC_ONLY,
                                "pm", stats_);
    stats_.rays = tracer_.rays();
    built_ = true;
    log::verbose("pm: global map " + std::to_string(global_.count) + " photons, caustic map " +
                 std::to_string(caustic_.count) + " photons");
    if (cache_) cache_->build(params, global_, started, stop_flag());
  }
  launch(params, film);
}

void PhotonMapper::launch(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  cl_uint next = kernel_.args(first_arg_, params_, pm_params_, global_.nodes, global_.photons, global_.count,
                              caustic_.nodes, caustic_.photons, caustic_.count);
  if (cache_) {
    cache_->write_params();
    next = cache_->bind_image(kernel_, next);
  } else {
    next = no_cache_->bind_image(kernel_, next);
  }
  kernel_.args(next, film.sum(), film.sum_sq(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
