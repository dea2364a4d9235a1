#include "render/renderer.h"

#include "shared/aov_types.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <exception>
#include <thread>

#include <nlohmann/json.hpp>

#include "bvh/bvh.h"
#include "render/camera_setup.h"
#include "render/pass_schedule.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

// How a rank sends its devices' shares and vcm figures to rank 0 (gather_device_stats).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DeviceShare, name, label, samples, passes, busy_seconds)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(VcmStats, light_vertices, connections, merges, passes, tiles,
                                   grids, grid_seconds, first_radius, last_radius, alpha, pixel_radii,
                                   merge_first, light_per_pixel, light_paths_auto,
                                   pixel_radius_min,
                                   pixel_radius_max, pixel_radius_sum, pixel_radius_count,
                                   device_bytes)
// ... and what adds up of mlt's chains and ic's lookups (MetropolisStats::add_chains,
// IcStats::add_lookups).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MetropolisStats, chains, large_proposed, large_accepted,
                                   small_proposed, small_accepted, chains_by_depth)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(IcStats, lookups, records_used, misses)

struct Renderer::Lane {
  const cl::Context* ctx = nullptr;
  std::unique_ptr<SceneBuffers> scene;
  std::unique_ptr<Integrator> integrator;
  std::unique_ptr<Film> film;
  std::unique_ptr<AovPass> aov;  // with RenderSettings::aovs only
  // Its pass schedule: the samples of its next pass and the time one sample took in its last.
  uint64_t pass_spp = 1;
  double seconds_per_spp = 0.0;
  double last_seconds = 0.0;  // of the round just run
  bool watchdog_warned = false;
  DeviceShare share;
};

Renderer::Renderer(const cl::Context& ctx, const Scene& scene, const RenderSettings& settings)
    : Renderer(std::vector<const cl::Context*>{&ctx}, scene, settings) {}

Renderer::Renderer(const std::vector<const cl::Context*>& contexts, const Scene& scene,
                   const RenderSettings& settings, const Cluster* cluster)
    : cluster_(cluster ? cluster : &alone_), settings_(settings) {
  if (contexts.empty()) throw std::logic_error("a renderer needs a device");
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

  // One tree for every device of this process: the smallest of their leaf sizes.
  BvhBuildOptions bvh_options;
  bvh_options.max_leaf_size = kMaxLeafLanes;
  for (const cl::Context* c : contexts)
    bvh_options.max_leaf_size = std::min(bvh_options.max_leaf_size, bvh_max_leaf(c->device()));
  auto t0 = Clock::now();
  const Bvh bvh = build_bvh(scene.positions, scene.triangles, bvh_options);
  stats_.bvh_build_seconds = seconds_since(t0);
  stats_.bvh_max_leaf = bvh_options.max_leaf_size;
  stats_.bvh_depth = bvh.depth;
  stats_.bvh_nodes = bvh.nodes.size();
  stats_.bvh_wide_depth = bvh.wide_depth;
  stats_.bvh_wide_nodes = bvh.wide.size();
  stats_.triangles = scene.triangles.size();
  log::verbose("BVH: leaves of up to " + std::to_string(bvh_options.max_leaf_size) + " triangles, " +
               std::to_string(bvh.nodes.size()) + " nodes, depth " + std::to_string(bvh.depth) +
               " (4-wide: " + std::to_string(bvh.wide.size()) + " nodes, depth " + std::to_string(bvh.wide_depth) +
               "), built in " + std::to_string(stats_.bvh_build_seconds) + " s");

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
  const FlatScene flat = flatten_scene(scene, bvh, *env, settings_.mipmaps);
  stats_.texture_mip_bytes = flat.mip_texels * sizeof(uint32_t);
  stats_.emitters = flat.emissive_triangles;
  stats_.lights = static_cast<uint32_t>(flat.lights.size());
  const IntegratorInfo& row = integrator_info(settings_.integrator);
  const bool split = contexts.size() > 1 || cluster_->size() > 1;
  if (split && row.split == DeviceSplit::OneDevice)
    throw Error(ExitCode::Usage,
                "--integrator " + settings_.integrator + " renders on one device: its passes "
                "depend on the passes before them, so they cannot be split into sample ranges; "
                "name one --device (and run one process)");
  // vcm's per-pixel radii shrink with all the passes before, as sppm's: split over devices or
  // ranks it takes the pass rule, whose passes are independent (docs/scaling.md).
  if (split && settings_.integrator == "vcm" && settings_.vcm.pixel_radius) {
    if (settings_.vcm.shrink_given)
      throw Error(ExitCode::Usage,
                  "--vcm-shrink pixel renders on one device: each pixel's radius follows from the "
                  "passes before, so they cannot be split into sample ranges; name one --device "
                  "(and run one process), or take --vcm-shrink pass");
    settings_.vcm.pixel_radius = false;
    if (!settings_.vcm.alpha_given) settings_.vcm.alpha = kVcmPassAlpha;
  }
  // --vcm-light-paths auto's pilot times one device's passes, and every device's light
  // subpaths must draw disjoint sample indices: split, vcm traces one per pixel.
  if (split && settings_.integrator == "vcm" && settings_.vcm.light_per_pixel == 0)
    settings_.vcm.light_per_pixel = 1;
  if (flat.lights.empty() && row.needs_lights)
    log::warn("the scene has no lights (emissive surfaces, punctual lights or environment): "
              "the image will be black");
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
  params_.texture_cones = settings_.mipmaps ? 1u : 0u;
  params_.direct = settings_.direct;
  params_.mis = settings_.mis;
  params_.light_samples = std::max<uint32_t>(1, settings_.light_samples);
  params_.hemisphere = settings_.hemisphere;
  params_.rr = settings_.rr;
  params_.rr_absorb = settings_.rr_absorb;
  params_.branching = std::max<uint32_t>(1, settings_.branching);
  if (row.max_depth_cap) params_.max_depth = std::min(params_.max_depth, row.max_depth_cap);
  IntegratorConfig config{settings_.bdpt, settings_.pm,  settings_.sppm,     settings_.ao,
                          settings_.mlt,  settings_.ic,  settings_.vcm,      settings_.indirect,
                          {},             settings_.time_limit};
  config.vcm.planned_passes = settings_.spp;  // vcm passes are samples per pixel; 0: --time alone
  config.scale.diagonal = glm::length(scene.bounds().extent());
  config.scale.pixel_footprint = pixel_footprint(params_.camera, height_, scene.bounds());
  for (const cl::Context* ctx : contexts) {
    for (const auto& other : lanes_)
      if (other->ctx->device().id == ctx->device().id)
        throw Error(ExitCode::Usage, ctx->device().label() + " is named twice");
    auto lane = std::make_unique<Lane>();
    lane->ctx = ctx;
    lane->scene = std::make_unique<SceneBuffers>(*ctx, flat);
    lane->film = std::make_unique<Film>(*ctx, width_, height_, row.film == FilmKind::Splats,
                                        row.film == FilmKind::SampleSums);
    // Program from cache or source, then a warm-up launch: drivers such as PoCL compile the
    // kernel for its work-group size at the first launch, which belongs to start-up, not to
    // the first pass's timing.
    const auto t_kernel = Clock::now();
    lane->integrator = make_integrator(settings_.integrator, *ctx, *lane->scene, config);
    lane->integrator->warm_up(params_, *lane->film);
    if (settings_.aovs) {
      lane->aov = std::make_unique<AovPass>(*ctx, *lane->scene, width_, height_);
      lane->aov->warm_up(params_);
    }
    ctx->finish();
    stats_.kernel_seconds += seconds_since(t_kernel);
    lane->share.name = ctx->device().name;
    lane->share.label = ctx->device().label();
    lanes_.push_back(std::move(lane));
  }
  // Memory figures are one device's: every device holds the same.
  const Lane& first = *lanes_.front();
  stats_.scene_device_bytes = first.scene->device_bytes();
  stats_.film_device_bytes = first.film->device_bytes() + (first.aov ? first.aov->device_bytes() : 0);
  stats_.texture_device_bytes = first.scene->texture_bytes();
  // Not built from source this time: from the disk cache, or reused from the context.
  stats_.kernel_from_cache =
      first.integrator->build_info().from_cache || first.integrator->build_info().from_memory;
}

Renderer::~Renderer() = default;

const cl::DeviceInfo& Renderer::lanes_device(size_t i) const { return lanes_[i]->ctx->device(); }

FilmSums Renderer::film_sums() const {
  FilmSums sums = lanes_.front()->film->read();
  for (size_t i = 1; i < lanes_.size(); ++i) sums.add(lanes_[i]->film->read());
  if (cluster_->size() > 1) {
    cluster_->gather_to_root(sums.pieces(), [&](size_t piece, size_t offset, const void* chunk,
                                                 size_t bytes) {
      sums.add_chunk(piece, offset, chunk, bytes);
    });
  }
  return sums;
}

FilmState Renderer::film_state(uint64_t samples_per_pixel) const {
  if (!lanes_.front()->film->sums_samples())
    throw Error(ExitCode::Usage, "checkpoints are not supported with --integrator " +
                                     settings_.integrator + " (its film is not a sum of samples)");
  const FilmSums sums = film_sums();
  FilmState s;
  s.width = width_;
  s.height = height_;
  s.samples_per_pixel = samples_per_pixel;
  // Four floats a pixel, as on the device.
  const float* sum = sums.sum.front().data();
  const float* sum_sq = sums.sum_sq.front().data();
  s.sum.assign(sum, sum + 4 * sums.sum.size());
  s.sum_sq.assign(sum_sq, sum_sq + 4 * sums.sum_sq.size());
  s.ray_counts = sums.rays;
  return s;
}

void Renderer::restore(const FilmState& s) {
  Film& film = *lanes_.front()->film;  // the others stay empty: the sums are added at the end
  if (!film.sums_samples())
    throw Error(ExitCode::Usage, "--resume is not supported with --integrator " +
                                     settings_.integrator + " (its film is not a sum of samples)");
  if (s.width != width_ || s.height != height_)
    throw Error(ExitCode::Usage, "checkpoint is " + std::to_string(s.width) + "x" +
                                     std::to_string(s.height) + ", this render " +
                                     std::to_string(width_) + "x" + std::to_string(height_));
  // The other ranks start empty: rank 0's film holds the checkpoint's sums.
  if (cluster_->root()) {
    film.sum().write(s.sum.data(), s.sum.size() * sizeof(float));
    film.sum_sq().write(s.sum_sq.data(), s.sum_sq.size() * sizeof(float));
    film.ray_counts().write(s.ray_counts.data(), s.ray_counts.size() * sizeof(uint32_t));
  }
  start_spp_ = s.samples_per_pixel;
}

void Renderer::for_each_lane(const std::function<bool(size_t)>& busy,
                             const std::function<void(size_t)>& f) {
  // One device runs on this thread; several, one host thread each, since an integrator's pass
  // may wait on its device in between launches (bdpt's tiles, pm's map build).
  std::vector<std::thread> threads;
  std::vector<std::exception_ptr> errors(lanes_.size());
  for (size_t i = 1; i < lanes_.size(); ++i)
    if (busy(i))
      threads.emplace_back([&, i] {
        try {
          f(i);
        } catch (...) {
          errors[i] = std::current_exception();
        }
      });
  try {
    if (busy(0)) f(0);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

void Renderer::run_round(const std::vector<uint64_t>& first, const std::vector<uint64_t>& n) {
  for_each_lane([&](size_t i) { return n[i] > 0; },
                [&](size_t i) {
                  Lane& lane = *lanes_[i];
                  dev::RenderParams p = params_;
                  p.sample_offset = static_cast<uint32_t>(first[i]);
                  p.samples_per_pass = static_cast<uint32_t>(n[i]);
                  const auto t0 = Clock::now();
                  lane.integrator->render_pass(p, *lane.film);
                  if (lane.aov) lane.aov->add(p);
                  lane.ctx->finish();
                  lane.last_seconds = seconds_since(t0);
                });
}

void Renderer::share_setup(size_t all, size_t mine) {
  const uint64_t items = lanes_.front()->integrator->setup_items(params_);
  if (items == 0) return;
  // Equal shares in device and rank order (no device has been timed yet), each device's
  // part in its own slot, then every rank's parts to every device.
  // A rank whose devices fail says so before the exchange (Cluster::agree), so that no rank
  // waits there for one that has given up.
  const size_t k = lanes_.size();
  std::vector<std::string> parts(k);
  cluster_->agree(capture([&] {
    for_each_lane([](size_t) { return true; },
                  [&](size_t i) {
                    const uint64_t first = items * (mine + i) / all;
                    const uint64_t last = items * (mine + i + 1) / all;
                    Lane& lane = *lanes_[i];
                    parts[i] = lane.integrator->setup_part(params_, *lane.film, first, last - first);
                  });
  }));
  std::string local = std::move(parts[0]);
  for (size_t i = 1; i < k; ++i) local += parts[i];
  const std::string whole = cluster_->all_gather_bytes(std::move(local));
  cluster_->agree(capture([&] {
    for_each_lane([](size_t) { return true; },
                  [&](size_t i) {
                    Lane& lane = *lanes_[i];
                    lane.integrator->setup_finish(params_, *lane.film, whole);
                    lane.ctx->finish();
                  });
  }));
}

void Renderer::gather_device_stats() {
  stats_.devices.clear();
  stats_.connections = 0;
  stats_.vcm = VcmStats{};
  // The photon maps, mlt's normalisation and ic's cache are alike on every device: the first
  // device's figures, with every device's chains and cache lookups added.
  const Integrator& first = *lanes_.front()->integrator;
  stats_.photons = first.photon_stats();
  stats_.metropolis = first.metropolis_stats();
  stats_.ic = first.ic_stats();
  for (size_t i = 0; i < lanes_.size(); ++i) {
    const Integrator& integrator = *lanes_[i]->integrator;
    stats_.connections += integrator.connections();
    stats_.devices.push_back(lanes_[i]->share);
    stats_.vcm.add(integrator.vcm_stats());
    if (i == 0) continue;
    stats_.metropolis.add_chains(integrator.metropolis_stats());
    stats_.ic.add_lookups(integrator.ic_stats());
  }
  if (cluster_->size() == 1) return;
  // Other ranks' figures, their devices labelled with their rank, as JSON text.
  if (!cluster_->root()) {
    const nlohmann::json j = {{"connections", stats_.connections},
                              {"devices", stats_.devices},
                              {"vcm", stats_.vcm},
                              {"mlt", stats_.metropolis},
                              {"ic", stats_.ic}};
    cluster_->gather_text_to_root(j.dump(), {});
    return;
  }
  for (DeviceShare& d : stats_.devices) d.label = "rank 0: " + d.label;
  int rank = 0;
  cluster_->gather_text_to_root({}, [&](const std::string& text) {
    ++rank;
    const nlohmann::json j = nlohmann::json::parse(text);
    stats_.connections += j.at("connections").get<uint64_t>();
    for (DeviceShare d : j.at("devices").get<std::vector<DeviceShare>>()) {
      d.label = "rank " + std::to_string(rank) + ": " + d.label;
      stats_.devices.push_back(std::move(d));
    }
    stats_.vcm.add(j.at("vcm").get<VcmStats>());
    stats_.metropolis.add_chains(j.at("mlt").get<MetropolisStats>());
    stats_.ic.add_lookups(j.at("ic").get<IcStats>());
  });
}

std::vector<NamedChannel> Renderer::gathered_layers(uint64_t done) const {
  // Every device's, each already divided by the render's samples, added (and every rank's, on
  // rank 0).
  std::vector<NamedChannel> layers = lanes_.front()->integrator->layers(done);
  for (size_t i = 1; i < lanes_.size(); ++i) {
    const std::vector<NamedChannel> more = lanes_[i]->integrator->layers(done);
    for (size_t l = 0; l < layers.size() && l < more.size(); ++l)
      for (size_t j = 0; j < layers[l].image.rgb.size(); ++j)
        layers[l].image.rgb[j] += more[l].image.rgb[j];
  }
  if (cluster_->size() > 1 && !layers.empty()) {
    std::vector<Cluster::Piece> pieces;
    for (const NamedChannel& l : layers)
      pieces.push_back({l.image.rgb.data(), l.image.rgb.size() * sizeof(float)});
    cluster_->gather_to_root(pieces, [&](size_t l, size_t offset, const void* chunk, size_t bytes) {
      float* to = layers.at(l).image.rgb.data() + offset / sizeof(float);
      const float* from = static_cast<const float*>(chunk);
      for (size_t j = 0; j < bytes / sizeof(float); ++j) to[j] += from[j];
    });
  }
  return layers;
}

std::vector<NamedChannel> Renderer::gathered_aovs() const {
  // Rank 0's first device's sums first: it took sample 0, whose material index they keep.
  std::vector<dev::AovSums> sums = lanes_.front()->aov->sums();
  for (size_t i = 1; i < lanes_.size(); ++i) {
    const std::vector<dev::AovSums> other = lanes_[i]->aov->sums();
    AovPass::add(sums.data(), other.data(), sums.size());
  }
  if (cluster_->size() > 1)
    cluster_->gather_to_root({{sums.data(), sums.size() * sizeof(sums[0])}},
                             [&](size_t, size_t offset, const void* chunk, size_t bytes) {
                               AovPass::add(sums.data() + offset / sizeof(dev::AovSums),
                                            static_cast<const dev::AovSums*>(chunk),
                                            bytes / sizeof(dev::AovSums));
                             });
  return AovPass::aov_layers(sums, width_, height_, settings_.aovs);
}

RenderOutput Renderer::render(const std::atomic<bool>* stop, const Progress& progress) {
  RenderOutput out;
  const Cluster& cluster = *cluster_;
  const uint64_t target = settings_.spp;  // 0: until the time limit
  const double limit = settings_.time_limit;
  Lane& lane0 = *lanes_.front();
  const double pass_seconds = settings_.target_pass_seconds > 0.0 ? settings_.target_pass_seconds
                             : lane0.ctx->device().is_gpu()        ? 0.03
                                                                   : 0.1;
  for (auto& lane : lanes_) lane->integrator->set_stop(stop);
  // Pass sizes follow the clock (each pass aims at pass_seconds), except for integrators
  // whose image depends on the split (pass_invariant) in a render with a sample count: they
  // double from 1 spp up to kFixedPassSamples samples a pass, so that the same seed gives
  // the same image however fast or busy the machine is. A --time render stops by the
  // clock and is not reproducible anyway.
  constexpr uint64_t kFixedPassSamples = uint64_t(1) << 20;
  PassSchedule schedule;
  schedule.pass_seconds = pass_seconds;
  schedule.by_clock = target == 0 || lane0.integrator->pass_invariant();
  schedule.fixed_cap = std::max<uint64_t>(1, kFixedPassSamples / (uint64_t(width_) * height_));
  const auto start = Clock::now();
  uint64_t done = start_spp_;
  const size_t k = lanes_.size();

  // Every rank's devices, in rank order, are the pass's "all devices": how many each rank has,
  // and where this rank's come in that order.
  const std::vector<double> counts = cluster.all_gather({double(k)});
  size_t all = 0, mine = 0;
  for (int r = 0; r < int(counts.size()); ++r) {
    if (r == cluster.rank()) mine = all;
    all += size_t(counts[r]);
  }
  for (size_t i = 0; i < k; ++i) lanes_[i]->integrator->set_device_index(uint32_t(mine + i));
  // Start-up work the integrator shares out over every device of every rank (mlt's bootstrap),
  // once, counted in the render's time as its first pass would have been.
  if (!setup_shared_) share_setup(all, mine);
  setup_shared_ = true;

  // A resumed render's AOVs: the checkpoint holds the image's sums only, so the AOV samples
  // it covered are taken again first (on rank 0's first device, which holds sample 0).
  if (lane0.aov && start_spp_ > 0 && cluster.root()) {
    dev::RenderParams p = params_;
    p.sample_offset = 0;
    p.samples_per_pass = static_cast<uint32_t>(std::min<uint64_t>(start_spp_, AOV_MAX_SAMPLES));
    lane0.aov->add(p);
  }
  // The sample target or the time limit ends the render after a pass, decided once, right
  // after it, so that the progress callback knows which pass is the last. The time limit
  // never ends it before the first pass: a render that took no sample has no image to write
  // (--time 1e-300 used to exit 0 without one).
  bool last = target != 0 && done >= target;
  double now = 0.0;
  std::vector<uint64_t> n(all), first(all);
  while (!last) {
    const double elapsed = seconds_since(start);

    // Each device's share of this pass: what its own schedule asks for, held to the time left
    // at its own speed. Every rank sends its devices' (after its stop flag) to all.
    std::vector<double> proposal = {stop && stop->load() ? 1.0 : 0.0};
    for (size_t i = 0; i < k; ++i) {
      const Lane& lane = *lanes_[i];
      uint64_t m = lane.pass_spp;
      if (limit > 0.0 && lane.seconds_per_spp > 0.0)
        m = std::min<uint64_t>(m, std::max<uint64_t>(1, uint64_t((limit - elapsed) / lane.seconds_per_spp)));
      if (settings_.max_samples_per_pass) m = std::min<uint64_t>(m, settings_.max_samples_per_pass);
      proposal.push_back(double(m));
    }
    const std::vector<double> proposals = cluster.all_gather(proposal);
    bool stopped = false;
    uint64_t want = 0;
    for (size_t r = 0, at = 0, lane = 0; r < counts.size(); ++r) {
      stopped |= proposals[at++] != 0.0;
      for (size_t i = 0; i < size_t(counts[r]); ++i, ++lane) want += n[lane] = uint64_t(proposals[at++]);
    }
    if (stopped) {
      out.interrupted = true;
      break;
    }
    // Near the sample target, all shares scaled down to what is left (so rank 0's first device
    // always works: it takes the render's sample 0).
    if (target && want > target - done) {
      n = share_samples(n, target - done);
      want = target - done;
    }
    if (done + want > 0xffffffffull) throw Error(ExitCode::Usage, "more than 2^32 samples per pixel");
    for (size_t i = 0, at = done; i < all; at += n[i], ++i) first[i] = at;

    const std::vector<uint64_t> my_first(first.begin() + mine, first.begin() + mine + k);
    const std::vector<uint64_t> my_n(n.begin() + mine, n.begin() + mine + k);
    cluster.agree(capture([&] { run_round(my_first, my_n); }));
    done += want;
    ++stats_.passes;

    // Several devices share a pass, which ends when the slowest share does; shares are whole
    // samples per pixel, so a pass of one sample each would leave a fast device idle for most
    // of it. Their passes are long enough for the slowest device to take kMinShareSamples, so
    // shares in proportion to speed round off by little.
    constexpr double kMinShareSamples = 8.0;
    std::vector<double> my_seconds;
    for (size_t i = 0; i < k; ++i) my_seconds.push_back(lanes_[i]->last_seconds);
    const std::vector<double> seconds = cluster.all_gather(my_seconds);
    double slowest = 0.0;
    for (size_t i = 0; i < all; ++i)
      if (n[i]) slowest = std::max(slowest, seconds[i] / double(n[i]));
    schedule.pass_seconds = all > 1 ? std::max(pass_seconds, kMinShareSamples * slowest) : pass_seconds;
    for (size_t i = 0; i < k; ++i) {
      const uint64_t m = my_n[i];
      if (!m) continue;
      Lane& lane = *lanes_[i];
      const double dt = lane.last_seconds;
      lane.seconds_per_spp = dt / double(m);
      lane.pass_spp = next_pass_samples(schedule, lane.pass_spp, m, dt);
      lane.share.samples += m;
      lane.share.passes += 1;
      lane.share.busy_seconds += dt;
      const cl::DeviceInfo& device = lane.ctx->device();
      if (m == 1 && dt > kWatchdogWarningSeconds && device.is_gpu() && !lane.watchdog_warned) {
        lane.watchdog_warned = true;
        log::warn("one sample per pixel took " + std::to_string(dt) + " s on '" + device.name +
                  "', and no pass is smaller: a display driver's watchdog (about 2 s on "
                  "Windows) may stop such kernels; a smaller --resolution or --max-depth "
                  "shortens every pass");
      }
    }
    // Rank 0's clock decides the time limit for all.
    std::vector<double> clock = {seconds_since(start)};
    cluster.broadcast(clock, 0);
    now = clock[0];
    last = (target != 0 && done >= target) || (limit > 0.0 && now >= limit);
    // The callback runs on every rank with the same arguments: what it does collectively
    // (snapshots, checkpoints) every rank does alike.
    if (progress) cluster.agree(capture([&] { progress(done, target, now, last); }));
  }
  stats_.render_seconds = seconds_since(start);
  const auto gather_start = Clock::now();
  const FilmSums sums = film_sums();
  stats_.film_gather_seconds = seconds_since(gather_start);
  out.film = resolve_film(sums, done);
  // Shares, connections, vcm's figures, mlt's chains and ic's lookups add up over every device
  // of every rank.
  gather_device_stats();
  out.layers = gathered_layers(done);
  if (lane0.aov) out.aovs = gathered_aovs();
  out.stats = stats_;
  return out;
}

}  // namespace clpt
