#include "app/cli.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <optional>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sys/resource.h>
#include <unistd.h>

#include "app/bdpt_mosaic.h"
#include "cl/context.h"
#include "cl/programs.h"
#include "io/image_io.h"
#include "io/output_path.h"
#include "options.h"
#include "render/light_table.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "integrators/integrator.h"
#include "shared/photon_types.h"
#include "shared/indirect_types.h"
#include "shared/vcm_types.h"
#include "stats/image_stats.h"
#include "util/error.h"
#include "util/log.h"
#include "util/progress.h"

namespace clpt {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_signal(int) {
  // First signal: finish the pass in flight and save. Second: leave at once, output untouched.
  if (g_stop.exchange(true)) _exit(static_cast<int>(ExitCode::Interrupted));
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

double peak_rss_mib() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void write_stats(const std::string& where, const nlohmann::json& j) {
  const std::string text = j.dump(2) + "\n";
  if (where == "-") {
    std::cout << text << std::flush;
    return;
  }
  const std::string tmp = where + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!(f << text) || !f.flush()) {
      std::remove(tmp.c_str());
      throw Error(ExitCode::Output, "cannot write statistics to " + where);
    }
  }
  if (std::rename(tmp.c_str(), where.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(ExitCode::Output, "cannot write statistics to " + where);
  }
}

// --view and --exposure (checked by the options parser), and their record in the image's
// metadata: an EXR keeps linear radiance but says how its PNG would have been shown.
DisplaySettings display_settings(const Options& opt, ImageMetadata* meta) {
  DisplaySettings d;
  d.view = parse_view_transform(opt.view).value_or(ViewTransform::Standard);
  d.exposure = opt.exposure;
  meta->strings.emplace_back("clpt:view", view_transform_name(d.view));
  meta->floats.emplace_back("clpt:exposure", d.exposure);
  return d;
}

// --bdpt-mosaic: the strategies of bdpt as one image (app/bdpt_mosaic.h).
int run_mosaic(const Options& opt, const cl::Context& ctx, const Scene& scene,
               const RenderSettings& settings, const std::string& device_name) {
  log::info("rendering the bdpt strategy mosaic of " + opt.scene + " on " + device_name);
  const bool tty = ::isatty(STDERR_FILENO);
  ProgressBar bar(log::level() >= log::Level::Normal && tty);
  const auto start = std::chrono::steady_clock::now();
  const MosaicResult m = render_bdpt_mosaic(
      ctx, scene, settings, opt.bdpt_unweighted, &g_stop, [&](uint32_t done, uint32_t total) {
        bar.update(done, total,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                   0.0, "strategies");
      });
  bar.finish();
  if (m.cells_rendered == 0) {
    log::warn("no strategy was rendered; " + opt.output + " was not written");
    return m.interrupted ? static_cast<int>(ExitCode::Interrupted) : 0;
  }
  ImageMetadata meta;
  meta.strings = {{"Software", std::string("clpt ") + CLPT_VERSION},
                  {"clpt:integrator", "bdpt"},
                  {"clpt:bdpt_mosaic", opt.bdpt_unweighted ? "unweighted" : "weighted"},
                  {"clpt:device", device_name},
                  {"clpt:scene", opt.scene}};
  meta.ints = {{"clpt:spp", int(m.samples_per_pixel)}, {"clpt:seed", int(opt.seed)}};
  const DisplaySettings display = display_settings(opt, &meta);
  write_image(opt.output, m.image, meta, {}, display);
  log::info((m.interrupted ? "interrupted: " : "") + std::to_string(m.cells_rendered) + " of " +
            std::to_string(m.cells_total) + " strategies at " + std::to_string(m.samples_per_pixel) +
            " spp, wrote " + opt.output + " (rows: 0 to 4 bounces; columns: S = 0, 1, ...)");
  return m.interrupted ? static_cast<int>(ExitCode::Interrupted) : 0;
}

int run(const Options& opt) {
  using Clock = std::chrono::steady_clock;
  if (opt.list_devices) {
    std::cout << "OpenCL devices:\n" << cl::describe_devices(cl::list_devices());
    return 0;
  }
  install_signal_handlers();  // from here on, Ctrl-C stops cleanly and saves what was rendered
  if (!opt.kernel_dir.empty()) ::setenv("CLPT_KERNEL_DIR", opt.kernel_dir.c_str(), 1);
  if (!opt.dump_kernels.empty()) {
    const size_t n = programs::dump(opt.dump_kernels);
    log::info("wrote " + std::to_string(n) + " kernel programs and programs.tsv to " +
              opt.dump_kernels);
    return 0;
  }
  {
    std::vector<NamedPath> outputs = {{"output", opt.output}}, inputs = {{"the scene", opt.scene}};
    if (opt.stats && *opt.stats != "-") outputs.push_back({"--stats", *opt.stats});
    if (!opt.checkpoint.empty()) outputs.push_back({"--checkpoint", opt.checkpoint});
    if (!opt.env.empty()) inputs.push_back({"--env", opt.env});
    if (!opt.reference.empty()) inputs.push_back({"--reference", opt.reference});
    if (!opt.resume.empty()) inputs.push_back({"--resume", opt.resume});
    check_outputs_apart(outputs, inputs, {{"--checkpoint", "--resume"}});
  }
  check_output_path(opt.output);
  if (opt.stats && *opt.stats != "-") check_writable_path(*opt.stats, "--stats");
  if (!opt.checkpoint.empty()) check_writable_path(opt.checkpoint, "--checkpoint");

  // A reference image's header is read before any work, so a bad one fails fast; its pixels
  // once the render's size is known and the header matches it (no allocation sized by an
  // unchecked header).
  std::optional<ImageSize> reference_size;
  if (!opt.reference.empty()) {
    ImageLimits any_film;  // a reference is compared with the film: no larger than the largest
    any_film.max_dimension = kMaxFilmSide;
    any_film.max_pixels = uint64_t{kMaxFilmSide} * kMaxFilmSide;
    any_film.raise = "no film is larger";
    try {
      reference_size = read_image_size(opt.reference, any_film);
    } catch (const Error& e) {
      throw Error(e.code(), std::string("--reference ") + e.what());
    }
  }
  LoadOptions load_options;
  load_options.lenient = opt.lenient;
  for (const std::string& spec : opt.limits) load_options.limits.set(spec);
  // The environment map, read whole before the scene and the device: a bad one fails fast,
  // and what a refused one costs is its own bytes, not the device's set-up as well.
  ImageLimits env_limits;
  env_limits.max_dimension = load_options.limits.image_dimension;
  env_limits.max_pixels = load_options.limits.image_pixels;
  std::shared_ptr<Environment> environment;
  if (!opt.env.empty()) {
    environment = std::make_shared<Environment>(load_environment(opt.env, opt.env_scale, opt.env_rotate, env_limits));
    environment->background = glm::vec3(opt.background[0], opt.background[1], opt.background[2]);
  }

  auto t0 = Clock::now();
  const Scene scene = load_gltf(opt.scene, load_options);
  const double load_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  log::verbose("scene " + opt.scene + ": " + std::to_string(scene.triangles.size()) +
               " triangles, " + std::to_string(scene.materials.size()) + " materials, " +
               std::to_string(scene.cameras.size()) + " cameras, loaded in " +
               std::to_string(load_seconds) + " s");

  const cl::DeviceInfo device = cl::select_device(opt.device);
  log::verbose("device: " + device.label() + ", " + device.version + ", driver " +
               device.driver_version);
  cl::Context ctx(device);

  RenderSettings settings;
  settings.width = opt.width;
  settings.height = opt.height;
  settings.spp = opt.spp;
  settings.time_limit = opt.time_limit;
  settings.target_pass_seconds = opt.pass_seconds;
  settings.max_depth = opt.max_depth;
  settings.seed = opt.seed;
  settings.integrator = opt.integrator;
  settings.camera = opt.camera;
  settings.env_file = opt.env;
  settings.env_limits = env_limits;
  settings.environment = environment;
  settings.env_scale = opt.env_scale;
  settings.env_rotation = opt.env_rotate;
  settings.background = glm::vec3(opt.background[0], opt.background[1], opt.background[2]);
  settings.aperture = opt.aperture;
  settings.focus_distance = opt.focus_distance;
  settings.sampler = opt.sampler == "stratified" ? dev::SAMPLER_STRATIFIED
                     : opt.sampler == "lhs"      ? dev::SAMPLER_LHS
                     : opt.sampler == "sobol"    ? dev::SAMPLER_SOBOL
                                                 : dev::SAMPLER_INDEPENDENT;
  settings.direct = opt.direct == "light" ? dev::DIRECT_LIGHT
                    : opt.direct == "bsdf" ? dev::DIRECT_BSDF
                                           : dev::DIRECT_MIS;
  settings.mis = opt.mis == "balance" ? dev::MIS_BALANCE : dev::MIS_POWER;
  settings.light_samples = opt.light_samples;
  settings.hemisphere = opt.hemisphere == "cosine"    ? dev::HEMISPHERE_COSINE
                        : opt.hemisphere == "uniform" ? dev::HEMISPHERE_UNIFORM
                                                      : dev::HEMISPHERE_BSDF;
  settings.rr = opt.rr == "throughput" ? dev::RR_THROUGHPUT : dev::RR_FIXED;
  if (settings.rr == dev::RR_FIXED) settings.rr_absorb = std::stof(opt.rr.substr(6));
  settings.rr_depth = opt.rr_depth;
  settings.branching = opt.branching;
  settings.ao_radius = opt.ao_radius;
  if (!opt.bdpt_strategy.empty()) parse_strategy(opt.bdpt_strategy, &settings.bdpt_s, &settings.bdpt_t);
  settings.bdpt_unweighted = opt.bdpt_unweighted;
  settings.bdpt_lvc = opt.bdpt_lvc;
  settings.bdpt_memory_bytes = size_t(opt.bdpt_memory_mib) << 20;
  settings.photons = opt.photons;
  settings.caustic_photons = opt.caustic_photons;
  settings.final_gather = opt.final_gather;
  settings.knn = opt.knn;
  settings.pm_max_radius = opt.pm_max_radius;
  settings.pm_filter = opt.pm_filter == "box"            ? dev::PHOTON_FILTER_BOX
                       : opt.pm_filter == "epanechnikov" ? dev::PHOTON_FILTER_EPANECHNIKOV
                                                         : dev::PHOTON_FILTER_CONE;
  settings.sppm_radius = opt.sppm_radius;
  settings.sppm_alpha = opt.sppm_alpha;
  settings.mlt.multiplexed = opt.mlt_mode == "mmlt";
  settings.mlt.chains = opt.mlt_chains;
  settings.mlt.importance_tile = opt.mlt_target == "tile" ? kMltTile : 0u;
  settings.mlt.bootstrap = opt.mlt_bootstrap;
  settings.mlt.large_step = opt.mlt_large_step;
  settings.mlt.sigma = opt.mlt_sigma;
  settings.ic.error = opt.ic_error;
  settings.ic.rays = opt.ic_rays;
  settings.ic.min_spacing = opt.ic_min_spacing;
  settings.ic.max_spacing = opt.ic_max_spacing;
  settings.ic.gradients = !opt.ic_no_gradients;
  settings.ic.show_records = opt.ic_show_records;
  settings.ic.photons = opt.ic_photons;
  settings.final_gather_cache = opt.final_gather_cache;
  settings.vcm.mode = opt.vcm_mode == "bpt"   ? dev::VCM_MODE_BPT
                      : opt.vcm_mode == "ppm" ? dev::VCM_MODE_PPM
                      : opt.vcm_mode == "lt"  ? dev::VCM_MODE_LT
                      : opt.vcm_mode == "pt"  ? dev::VCM_MODE_PT
                                              : dev::VCM_MODE_VCM;
  settings.indirect = opt.indirect == "source"    ? dev::INDIRECT_SOURCE
                      : opt.indirect == "surface" ? dev::INDIRECT_SURFACE
                                                  : dev::INDIRECT_RECEIVER;
  settings.vcm.radius = opt.vcm_radius;
  settings.vcm.alpha = opt.vcm_alpha;
  if (opt.bdpt_mosaic) return run_mosaic(opt, ctx, scene, settings, device.name);
  // Problems of the scene the renderer finds (no triangles, a camera whose default image no
  // film holds) name the scene's file, as the loader's do.
  std::optional<Renderer> made;
  try {
    made.emplace(ctx, scene, settings);
  } catch (const Error& e) {
    if (e.code() != ExitCode::BadInput) throw;
    throw Error(ExitCode::BadInput, opt.scene + ": " + e.what());
  }
  Renderer& renderer = *made;
  std::optional<Image> reference;
  if (reference_size) {
    if (reference_size->width != renderer.width() || reference_size->height != renderer.height())
      throw Error(ExitCode::Usage, "--reference " + opt.reference + " is " +
                                       std::to_string(reference_size->width) + "x" +
                                       std::to_string(reference_size->height) + " but the render is " +
                                       std::to_string(renderer.width()) + "x" +
                                       std::to_string(renderer.height()) + " (use --resolution)");
    ImageLimits exact;
    exact.max_dimension = std::max(renderer.width(), renderer.height());
    exact.max_pixels = uint64_t(renderer.width()) * renderer.height();
    exact.raise = "the render's size";
    reference = read_image(opt.reference, exact);
  }

  // Everything a checkpoint's sums depend on; a resume must match it exactly.
  std::error_code ec;
  const std::string signature = nlohmann::json{
      {"clpt", CLPT_VERSION},
      {"scene", std::filesystem::weakly_canonical(opt.scene, ec).string()},
      {"triangles", scene.triangles.size()},
      {"vertices", scene.positions.size()},
      {"resolution", {renderer.width(), renderer.height()}},
      {"camera", opt.camera},
      {"integrator", opt.integrator},
      {"max_depth", opt.max_depth},
      {"seed", opt.seed},
      {"sampler", opt.sampler},
      // Stratified and lhs divide each dimension into --spp strata: the total must match.
      {"strata", (opt.sampler == "stratified" || opt.sampler == "lhs") ? opt.spp : 0},
      {"estimator", {opt.direct, opt.mis, opt.light_samples, opt.hemisphere, opt.rr,
                     opt.rr_depth, opt.branching, opt.ao_radius}}}.dump();
  if (!opt.resume.empty()) {
    renderer.restore(read_checkpoint(opt.resume, signature));
    log::info("resuming from " + opt.resume);
  }
  double last_checkpoint = 0.0, last_save = 0.0;
  // The image's metadata for `spp` samples after `seconds` of rendering (the final write and
  // --save-every's).
  auto image_metadata = [&](uint64_t spp, double seconds) {
    ImageMetadata meta;
    meta.strings = {{"Software", std::string("clpt ") + CLPT_VERSION},
                    {"clpt:integrator", opt.integrator},
                    {"clpt:device", device.name},
                    {"clpt:scene", opt.scene}};
    meta.ints = {{"clpt:spp", int(spp)}, {"clpt:seed", int(opt.seed)}, {"clpt:max_depth", int(opt.max_depth)}};
    meta.floats = {{"clpt:render_seconds", float(seconds)}};
    return meta;
  };

  log::info("rendering " + opt.scene + " at " + std::to_string(renderer.width()) + "x" +
            std::to_string(renderer.height()) + " with " + opt.integrator + " on " + device.name);
  // Progress: a bar on a terminal; with --reference, the relMSE so far, at most once a
  // second (it reads the film back), on the bar or as log lines when stderr is not a terminal.
  const bool tty = ::isatty(STDERR_FILENO);
  ProgressBar bar(log::level() >= log::Level::Normal && tty);
  double last_report = 0.0;
  const RenderOutput out = renderer.render(&g_stop, [&](uint64_t done, uint64_t target, double t, bool last) {
    std::string note;
    if (reference && t - last_report >= 1.0) {
      last_report = t;
      const double rel_mse = compare_images(renderer.snapshot(done).mean, *reference).rel_mse;
      char buf[64];
      std::snprintf(buf, sizeof buf, "relMSE %.4g", rel_mse);
      note = buf;
      if (!tty) log::info(std::to_string(done) + " spp, " + std::to_string(t) + " s: " + note);
    }
    bar.update(done, target, t, opt.time_limit, note);
    if (!opt.checkpoint.empty() && !last && t - last_checkpoint >= opt.checkpoint_interval) {
      last_checkpoint = t;
      write_checkpoint(opt.checkpoint, signature, renderer.film_state(done));
    }
    // --save-every: the image so far, written as the final one is (temporary file, rename), so a
    // viewer that reloads never sees half a file; not after the last pass, which the final
    // write follows at once.
    if (opt.save_every > 0.0 && !last && done > 0 && t - last_save >= opt.save_every) {
      last_save = t;
      ImageMetadata meta = image_metadata(done, t);
      const DisplaySettings display = display_settings(opt, &meta);
      write_image(opt.output, renderer.snapshot(done).mean, meta, {}, display);
      log::verbose("saved " + std::to_string(done) + " spp to " + opt.output);
    }
  });
  bar.finish();

  const FilmResult& film = out.film;
  const RenderStats& st = out.stats;
  const double paths = double(film.samples_per_pixel) * renderer.width() * renderer.height();
  const double secs = st.render_seconds > 0.0 ? st.render_seconds : 1e-9;

  ImageMetadata meta = image_metadata(film.samples_per_pixel, st.render_seconds);
  if (!opt.checkpoint.empty() && film.samples_per_pixel > 0)
    write_checkpoint(opt.checkpoint, signature, renderer.film_state(film.samples_per_pixel));
  if (film.samples_per_pixel > 0) {
    std::vector<NamedChannel> layers;
    if (opt.variance)
      layers.push_back({kVarianceLayer, variance_of_mean(film.variance, film.samples_per_pixel)});
    if (opt.vcm_merged)
      for (const NamedChannel& l : out.layers)
        if (l.name == "merged") layers.push_back(l);
    const DisplaySettings display = display_settings(opt, &meta);
    write_image(opt.output, film.mean, meta, layers, display);
  } else {
    log::warn("no sample was taken; " + opt.output + " was not written");
  }

  log::info((out.interrupted ? "interrupted: " : "") + std::string("rendered ") +
            std::to_string(film.samples_per_pixel) + " spp in " + std::to_string(st.render_seconds) +
            " s (" + std::to_string(paths / secs / 1e6) +
            (integrator_info(opt.integrator).traces_light_paths           ? " M light paths/s)"
             : integrator_info(opt.integrator).options & OPTIONS_MLT ? " M mutations/s)"
                                                                     : " M camera paths/s)") +
            (film.samples_per_pixel > 0 ? ", wrote " + opt.output : std::string()));
  if (film.dropped_samples)
    log::warn(std::to_string(film.dropped_samples) + " NaN/Inf samples were dropped");

  if (opt.stats) {
    nlohmann::json j;
    j["scene"] = opt.scene;
    j["integrator"] = opt.integrator;
    j["device"] = {{"name", device.name},           {"platform", device.platform_name},
                   {"version", device.version},     {"driver", device.driver_version},
                   {"compute_units", device.compute_units}};
    j["resolution"] = {renderer.width(), renderer.height()};
    j["triangles"] = st.triangles;
    j["emitters"] = st.emitters;
    j["lights"] = st.lights;
    j["scene_load_seconds"] = load_seconds;
    j["bvh"] = {{"build_seconds", st.bvh_build_seconds},
                {"nodes", st.bvh_nodes},
                {"depth", st.bvh_depth}};
    j["kernel"] = {{"seconds", st.kernel_seconds}, {"from_cache", st.kernel_from_cache}};
    j["render_seconds"] = st.render_seconds;
    j["passes"] = st.passes;
    j["spp"] = film.samples_per_pixel;
    j["max_depth"] = opt.max_depth;
    // lt traces spp x width x height light paths: the same count, from the other end.
    const IntegratorInfo& row = integrator_info(opt.integrator);
    j[row.traces_light_paths ? "light_paths_per_second" : "camera_paths_per_second"] =
        paths / secs;
    if (row.options & OPTIONS_BDPT) {
      j["connections"] = st.connections;
      j["connections_per_second"] = double(st.connections) / secs;
    }
    // pm builds kd-trees over its maps, as ic does over the map its records read (--ic-photons);
    // sppm a hashed grid per pass.
    const bool kd_maps = !(row.options & OPTIONS_SPPM);
    if ((row.options & OPTIONS_PHOTONS) || ((row.options & OPTIONS_IC) && opt.ic_photons)) {
      const PhotonStats& ph = st.photons;
      j["photons"] = {
          {"paths", ph.paths},
          {"stored", ph.stored},
          {"rays", ph.rays},
          {"emit_seconds", ph.emit_seconds},
          {"paths_per_second", ph.emit_seconds > 0.0 ? double(ph.paths) / ph.emit_seconds : 0.0},
          {"bytes_per_photon", sizeof(dev::Photon) + (kd_maps ? sizeof(dev::KdNode) : sizeof(uint32_t))},
          {kd_maps ? "kdtree_build_seconds" : "grid_build_seconds", ph.build_seconds},
          {kd_maps ? "maps" : "grid_builds", ph.builds},
          {"device_bytes", ph.device_bytes}};
    }
    if (row.options & OPTIONS_MLT) {
      const MetropolisStats& m = st.metropolis;
      const uint64_t proposed = m.large_proposed + m.small_proposed;
      const auto rate = [](uint64_t a, uint64_t n) { return n ? double(a) / double(n) : 0.0; };
      j["mlt"] = {{"mode", opt.mlt_mode},
                  {"target", opt.mlt_target},
                  {"chains", m.chains},
                  {"dimensions", m.dims},
                  {"bootstrap_paths", m.bootstrap_paths},
                  {"bootstrap_seconds", m.bootstrap_seconds},
                  {"b", m.b},
                  {"b_standard_error", m.b_standard_error},
                  {"mutations", proposed},
                  {"mutations_per_second", double(proposed) / secs},
                  {"large_step_acceptance", rate(m.large_accepted, m.large_proposed)},
                  {"small_step_acceptance", rate(m.small_accepted, m.small_proposed)},
                  {"acceptance", rate(m.large_accepted + m.small_accepted, proposed)},
                  {"device_bytes", m.device_bytes}};
      if (opt.mlt_mode == "mmlt") {
        j["mlt"]["b_by_depth"] = m.b_by_depth;
        j["mlt"]["chains_by_depth"] = m.chains_by_depth;
      }
    }
    if ((row.options & OPTIONS_IC) || ((row.options & OPTIONS_PM) && opt.final_gather_cache)) {
      const IcStats& ic = st.ic;
      const bool photon_records = opt.ic_photons || opt.final_gather_cache;
      j["ic"] = {{"error", opt.ic_error},
                 {"gather", photon_records ? "photons" : "paths"},
                 {"records", ic.records},
                 {"rays_per_record", ic.rays_per_record},
                 {"placement_passes", ic.placement_passes},
                 {"refinements", ic.refinements},
                 {"candidates", ic.candidates},
                 {"build_seconds", ic.build_seconds},
                 {"record_seconds", ic.record_seconds},
                 {"records_per_second", ic.record_seconds > 0.0 ? double(ic.records) / ic.record_seconds : 0.0},
                 {"lookups", ic.lookups},
                 {"lookups_per_second", double(ic.lookups) / secs},
                 {"records_per_lookup", ic.lookups ? double(ic.records_used) / double(ic.lookups) : 0.0},
                 {"lookup_misses", ic.misses},
                 {"gradients", !opt.ic_no_gradients},
                 {"device_bytes", ic.device_bytes}};
    }
    if (row.options & OPTIONS_INDIRECT) j["indirect"] = {{"generator", opt.indirect}};
    if (row.options & OPTIONS_VCM) {
      const VcmStats& v = st.vcm;
      j["vcm"] = {{"mode", opt.vcm_mode},
                  {"passes", v.passes},
                  {"tiles_per_pass", v.tiles},
                  {"first_radius", v.first_radius},
                  {"last_radius", v.last_radius},
                  {"alpha", opt.vcm_alpha},
                  {"light_vertices", v.light_vertices},
                  {"connections", v.connections},
                  {"connections_per_second", double(v.connections) / secs},
                  {"merges", v.merges},
                  {"merges_per_second", double(v.merges) / secs},
                  {"grids", v.grids},
                  {"grid_seconds", v.grid_seconds},
                  {"device_bytes", v.device_bytes}};
    }
    // Rays of camera-side paths; photon rays are under "photons".
    j["rays"] = film.rays;
    j["rays_per_second"] = double(film.rays) / secs;
    j["dropped_samples"] = film.dropped_samples;
    // Variance of each pixel's estimate (sample variance / spp), averaged over pixels and
    // channels, and efficiency = 1 / (variance x seconds): comparable between estimators
    // rendered for any time, since variance of a mean falls as 1/time.
    const double mean_variance =
        film.samples_per_pixel > 0 && film.variance_available
            ? clpt::mean_variance(variance_of_mean(film.variance, film.samples_per_pixel))
            : 0.0;
    j["mean_variance"] = mean_variance;
    if (!film.variance_available) {
      // Splatted films (lt) have no per-pixel sample variance; use --reference for errors.
      j["mean_variance"] = nullptr;
      j["variance"] = "unavailable: " + opt.integrator +
                      (row.film == FilmKind::Progressive
                           ? " pixels are progressive estimates, not sample means"
                           : row.options & OPTIONS_MLT
                               ? " splats its chains' states into any pixel"
                               : " splats light paths into any pixel");
    }
    if (reference && film.samples_per_pixel > 0) {
      const ImageComparison c = compare_images(film.mean, *reference);
      j["reference"] = {{"file", opt.reference}, {"rel_mse", c.rel_mse}, {"mse", c.mse},
                        {"smape", c.smape}, {"efficiency", efficiency(c.rel_mse, secs)}};
    }
    j["efficiency"] = mean_variance > 0.0 ? 1.0 / (mean_variance * secs) : 0.0;
    if (!film.variance_available) j["efficiency"] = nullptr;
    j["estimator"] = {{"sampler", opt.sampler},       {"direct", opt.direct},
                      {"mis", opt.mis},               {"light_samples", opt.light_samples},
                      {"hemisphere", opt.hemisphere}, {"rr", opt.rr},
                      {"rr_depth", opt.rr_depth},     {"branching", opt.branching}};
    j["interrupted"] = out.interrupted;
    // Per triangle: the geometry's share (BVH, triangles, vertices, lights), textures apart.
    j["memory"] = {{"scene_device_bytes", st.scene_device_bytes},
                   {"texture_device_bytes", st.texture_device_bytes},
                   {"scene_device_bytes_per_triangle",
                    st.triangles ? double(st.scene_device_bytes - st.texture_device_bytes) /
                                       double(st.triangles)
                                 : 0.0},
                   {"film_device_bytes", st.film_device_bytes},
                   {"peak_host_rss_mib", peak_rss_mib()}};
    write_stats(*opt.stats, j);
  }
  return out.interrupted ? static_cast<int>(ExitCode::Interrupted) : 0;
}

}  // namespace

int run_cli(int argc, const char* const* argv) {
  try {
    const std::optional<Options> opt = parse_options(argc, argv);
    if (!opt) return 0;
    log::set_level(opt->quiet ? log::Level::Quiet
                              : opt->verbose ? log::Level::Verbose : log::Level::Normal);
    return run(*opt);
  } catch (const Error& e) {
    log::error(e.what());
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    log::error("out of host memory");
    return static_cast<int>(ExitCode::Device);
  } catch (const std::exception& e) {
    log::error(std::string("internal error: ") + e.what());
    return 70;
  }
}

}  // namespace clpt
