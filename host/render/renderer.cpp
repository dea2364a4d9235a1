#include "render/renderer.h"

#include "shared/aov_types.h"

#include <algorithm>
#include <cmath>

#include "bvh/bvh.h"
#include "render/camera_setup.h"
#include "render/pass_schedule.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

Renderer::Renderer(const cl::Context& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx), settings_(settings) {
  if (settings_.spp == 0 && !(settings_.time_limit > 0.0))
    throw Error(ExitCode::Usage, "a render needs a sample count or a time limit");
  if (settings_.spp == 0 &&
      (settings_.sampler == dev::SAMPLER_STRATIFIED || settings_.sampler == dev::SAMPLER_LHS))
    throw Error(ExitCode::Usage,
                "the stratified and lhs samplers need --spp: they divide each dimension into "
                "as many strata as there are samples");
  if (settings_.rr == dev::RR_FIXED && !(settings_.rr_absorb >= 0.0f && settings_.rr_absorb < 1.0f))
    throw Error(ExitCode::Usage, "Russian roulette absorption must be in [0, 1)");
  if (scene.triangles.empty()) throw Error(ExitCode::BadInput, "the scene has no triangles to render");

  const Camera camera = choose_camera(scene, settings_.camera);
  width_ = settings_.width;
  height_ = settings_.height;
  if (width_ == 0 || height_ == 0) default_resolution(camera, &width_, &height_);

  auto t0 = Clock::now();
  const Bvh bvh = build_bvh(scene.positions, scene.triangles);
  stats_.bvh_build_seconds = seconds_since(t0);
  stats_.bvh_depth = bvh.depth;
  stats_.bvh_nodes = bvh.nodes.size();
  stats_.triangles = scene.triangles.size();
  log::verbose("BVH: " + std::to_string(bvh.nodes.size()) + " nodes, depth " +
               std::to_string(bvh.depth) + ", built in " + std::to_string(stats_.bvh_build_seconds) +
               " s");

  // --env (read by the caller, or here before anything renders) or the constant --background
  Environment loaded;
  const Environment* env = settings_.environment.get();
  if (!env) {
    if (!settings_.env_file.empty())
      loaded = load_environment(settings_.env_file, settings_.env_scale, settings_.env_rotation,
                                settings_.env_limits);
    loaded.background = settings_.background;
    env = &loaded;
  }
  const FlatScene flat = flatten_scene(scene, bvh, *env);
  stats_.emitters = flat.emissive_triangles;
  stats_.lights = static_cast<uint32_t>(flat.lights.size());
  const IntegratorInfo& row = integrator_info(settings_.integrator);
  if (flat.lights.empty() && row.needs_lights)
    log::warn("the scene has no lights (emissive surfaces, punctual lights or environment): "
              "the image will be black");
  scene_buffers_ = std::make_unique<SceneBuffers>(ctx_, flat);
  film_ = std::make_unique<Film>(ctx_, width_, height_, row.film == FilmKind::Splats,
                                 row.film == FilmKind::SampleSums);
  stats_.scene_device_bytes = scene_buffers_->device_bytes();
  stats_.film_device_bytes = film_->device_bytes();
  stats_.texture_device_bytes = scene_buffers_->texture_bytes();

  params_.camera = camera_data(camera, width_, height_);
  // A light path reaches a camera only through a non-delta direction: not an orthographic one.
  if (row.needs_perspective_camera && params_.camera.type == dev::CAMERA_ORTHOGRAPHIC)
    throw Error(ExitCode::Usage,
                "--integrator " + settings_.integrator + " needs a perspective camera: light "
                "paths cannot reach an orthographic camera (its rays all share one direction); "
                "use pt");
  set_thin_lens(params_.camera, settings_.aperture, settings_.focus_distance, scene.bounds());
  params_.width = width_;
  params_.height = height_;
  params_.max_depth = settings_.max_depth;
  params_.rr_depth = settings_.rr_depth;
  params_.seed = settings_.seed;
  params_.spp_total = static_cast<uint32_t>(std::min<uint64_t>(settings_.spp, 0xffffffffu));
  params_.sampler = settings_.sampler;
  params_.filter = settings_.filter;
  params_.filter_radius = settings_.filter_radius;
  // Integrators that splat apply the filter where they add (film/splat_filter.cl), the others
  // by drawing their camera samples from it (camera/pixel_filter.cl).
  params_.filter_splat = row.film == FilmKind::Splats ? 1u : 0u;
  params_.direct = settings_.direct;
  params_.mis = settings_.mis;
  params_.light_samples = std::max<uint32_t>(1, settings_.light_samples);
  params_.hemisphere = settings_.hemisphere;
  params_.rr = settings_.rr;
  params_.rr_absorb = settings_.rr_absorb;
  params_.branching = std::max<uint32_t>(1, settings_.branching);
  if (row.max_depth_cap) params_.max_depth = std::min(params_.max_depth, row.max_depth_cap);
  params_.bdpt_s = settings_.bdpt_s;
  params_.bdpt_t = settings_.bdpt_t;
  params_.bdpt_unweighted = settings_.bdpt_unweighted ? 1u : 0u;
  params_.bdpt_lvc = settings_.bdpt_lvc;
  params_.knn = std::clamp<uint32_t>(settings_.knn, 1, PM_KNN_MAX);
  params_.pm_max_radius = settings_.pm_max_radius > 0.0f
                              ? settings_.pm_max_radius
                              : 0.02f * glm::length(scene.bounds().extent());
  params_.pm_filter = settings_.pm_filter;
  params_.final_gather = settings_.final_gather;
  params_.sppm_radius = settings_.sppm_radius > 0.0f
                            ? settings_.sppm_radius
                            : 2.0f * pixel_footprint(params_.camera, height_, scene.bounds());
  if (!(params_.sppm_radius > 0.0f) || !std::isfinite(params_.sppm_radius))
    params_.sppm_radius = std::max(1e-3f * glm::length(scene.bounds().extent()), 1e-6f);
  params_.sppm_alpha = settings_.sppm_alpha;
  params_.ao_radius = settings_.ao_radius > 0.0f
                          ? settings_.ao_radius
                          : 0.1f * glm::length(scene.bounds().extent());

  // Program from cache or source, then a warm-up launch: drivers such as PoCL compile the
  // kernel for its work-group size at the first launch, which belongs to start-up, not to
  // the first pass's timing.
  t0 = Clock::now();
  IcConfig ic = settings_.ic;
  if (settings_.time_limit > 0.0) ic.refine_seconds = kIcRefineShare * settings_.time_limit;
  VcmConfig vcm = settings_.vcm;
  // One pixel footprint at the scene's centre: half sppm's default radius (the --vcm-radius
  // sweep in docs/BENCHMARKS.md, session 11).
  const bool vcm_radius_given = vcm.radius > 0.0f;
  if (!vcm_radius_given) vcm.radius = 0.5f * params_.sppm_radius;
  if (row.options & OPTIONS_VCM) {
    // A radius near the scene's size merges every light vertex at every camera vertex, and one
    // below float resolution at the scene's scale puts them all in one saturated grid cell:
    // either is a render that does not end. 10 % and 1e-6 of the diagonal bound it. The
    // default (a pixel footprint) is held inside the bounds: at a tiny resolution (8x8) a
    // footprint is above 10 %, and a radius nobody asked for is no usage error.
    const float diagonal = glm::length(scene.bounds().extent());
    if (!vcm_radius_given) vcm.radius = std::clamp(vcm.radius, 1e-6f * diagonal, 0.1f * diagonal);
    if (!(vcm.radius <= 0.1f * diagonal && vcm.radius >= 1e-6f * diagonal))
      throw Error(ExitCode::Usage, "--vcm-radius " + std::to_string(vcm.radius) +
                                       " is outside [1e-6, 0.1] times the scene's diagonal (" +
                                       std::to_string(diagonal) + ")");
  }
  integrator_ = make_integrator(
      settings_.integrator, ctx_, *scene_buffers_,
      IntegratorConfig{settings_.bdpt_memory_bytes, settings_.photons, settings_.caustic_photons,
                       settings_.final_gather_cache, settings_.mlt, ic, vcm, settings_.indirect});
  integrator_->warm_up(params_, *film_);
  if (settings_.aovs) {
    aov_ = std::make_unique<AovPass>(ctx_, *scene_buffers_, width_, height_);
    aov_->warm_up(params_);
    stats_.film_device_bytes += aov_->device_bytes();
  }
  ctx_.finish();
  stats_.kernel_seconds = seconds_since(t0);
  stats_.kernel_from_cache = integrator_->build_info().from_cache;
}

Renderer::~Renderer() = default;

FilmState Renderer::film_state(uint64_t samples_per_pixel) const {
  if (!film_->sums_samples())
    throw Error(ExitCode::Usage, "checkpoints are not supported with --integrator " +
                                     settings_.integrator + " (its film is not a sum of samples)");
  FilmState s;
  s.width = width_;
  s.height = height_;
  s.samples_per_pixel = samples_per_pixel;
  s.sum = film_->sum().read_vector<float>(film_->pixels() * 4);
  s.sum_sq = film_->sum_sq().read_vector<float>(film_->pixels() * 4);
  s.ray_counts = film_->ray_counts().read_vector<uint32_t>(film_->pixels());
  return s;
}

void Renderer::restore(const FilmState& s) {
  if (!film_->sums_samples())
    throw Error(ExitCode::Usage, "--resume is not supported with --integrator " +
                                     settings_.integrator + " (its film is not a sum of samples)");
  if (s.width != width_ || s.height != height_)
    throw Error(ExitCode::Usage, "checkpoint is " + std::to_string(s.width) + "x" +
                                     std::to_string(s.height) + ", this render " +
                                     std::to_string(width_) + "x" + std::to_string(height_));
  film_->sum().write(s.sum.data(), s.sum.size() * sizeof(float));
  film_->sum_sq().write(s.sum_sq.data(), s.sum_sq.size() * sizeof(float));
  film_->ray_counts().write(s.ray_counts.data(), s.ray_counts.size() * sizeof(uint32_t));
  start_spp_ = s.samples_per_pixel;
}

RenderOutput Renderer::render(const std::atomic<bool>* stop, const Progress& progress) {
  RenderOutput out;
  const uint64_t target = settings_.spp;  // 0: until the time limit
  const double limit = settings_.time_limit;
  const double pass_seconds = settings_.target_pass_seconds > 0.0 ? settings_.target_pass_seconds
                             : ctx_.device().is_gpu()              ? 0.03
                                                                   : 0.1;
  integrator_->set_stop(stop);
  // Pass sizes follow the clock (each pass aims at pass_seconds), except for integrators
  // whose image depends on the split (pass_invariant) in a render with a sample count: they
  // double from 1 spp up to kFixedPassSamples samples a pass, so that the same seed gives
  // the same image however fast or busy the machine is. A --time render stops by the
  // clock and is not reproducible anyway.
  constexpr uint64_t kFixedPassSamples = uint64_t(1) << 20;
  PassSchedule schedule;
  schedule.pass_seconds = pass_seconds;
  schedule.by_clock = target == 0 || integrator_->pass_invariant();
  schedule.fixed_cap = std::max<uint64_t>(1, kFixedPassSamples / (uint64_t(width_) * height_));
  bool watchdog_warned = false;
  const auto start = Clock::now();
  uint64_t done = start_spp_;
  uint64_t pass_spp = 1;
  double seconds_per_spp = 0.0;

  // The sample target or the time limit ends the render after a pass, decided once, right
  // after it, so that the progress callback knows which pass is the last. The time limit
  // never ends it before the first pass: a render that took no sample has no image to write
  // (--time 1e-300 used to exit 0 without one).
  // A resumed render's AOVs: the checkpoint holds the image's sums only, so the AOV samples
  // it covered are taken again first.
  if (aov_ && start_spp_ > 0) {
    dev::RenderParams p = params_;
    p.sample_offset = 0;
    p.samples_per_pass = static_cast<uint32_t>(std::min<uint64_t>(start_spp_, AOV_MAX_SAMPLES));
    aov_->add(p);
  }
  bool last = target != 0 && done >= target;
  while (!last) {
    if (stop && stop->load()) {
      out.interrupted = true;
      break;
    }
    const double elapsed = seconds_since(start);

    uint64_t n = pass_spp;
    if (target) n = std::min(n, target - done);
    if (limit > 0.0 && seconds_per_spp > 0.0)
      n = std::min<uint64_t>(n, std::max<uint64_t>(1, uint64_t((limit - elapsed) / seconds_per_spp)));
    if (settings_.max_samples_per_pass) n = std::min<uint64_t>(n, settings_.max_samples_per_pass);
    if (done + n > 0xffffffffull) throw Error(ExitCode::Usage, "more than 2^32 samples per pixel");

    dev::RenderParams p = params_;
    p.sample_offset = static_cast<uint32_t>(done);
    p.samples_per_pass = static_cast<uint32_t>(n);
    const auto t0 = Clock::now();
    integrator_->render_pass(p, *film_);
    if (aov_) aov_->add(p);
    ctx_.finish();
    const double dt = seconds_since(t0);
    done += n;
    ++stats_.passes;

    seconds_per_spp = dt / double(n);
    pass_spp = next_pass_samples(schedule, pass_spp, n, dt);
    if (n == 1 && dt > kWatchdogWarningSeconds && ctx_.device().is_gpu() && !watchdog_warned) {
      watchdog_warned = true;
      log::warn("one sample per pixel took " + std::to_string(dt) + " s on '" +
                ctx_.device().name + "', and no pass is smaller: a display driver's watchdog "
                "(about 2 s on Windows) may stop such kernels; a smaller --resolution or "
                "--max-depth shortens every pass");
    }
    const double now = seconds_since(start);
    last = (target != 0 && done >= target) || (limit > 0.0 && now >= limit);
    if (progress) progress(done, target, now, last);
  }
  stats_.render_seconds = seconds_since(start);
  out.film = film_->resolve(done);
  stats_.connections = integrator_->connections();
  stats_.photons = integrator_->photon_stats();
  stats_.metropolis = integrator_->metropolis_stats();
  stats_.ic = integrator_->ic_stats();
  stats_.vcm = integrator_->vcm_stats();
  out.layers = integrator_->layers(done);
  if (aov_) out.aovs = aov_->layers(settings_.aovs);
  out.stats = stats_;
  return out;
}

}  // namespace clpt
