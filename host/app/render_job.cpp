#include "app/render_job.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "app/bdpt_mosaic.h"
#include "app/stats_document.h"
#include "integrators/integrator.h"
#include "io/output_path.h"
#include "io/pfm.h"
#include "render/aov.h"
#include "render/checkpoint.h"
#include "render/light_table.h"
#include "scene/gltf_loader.h"
#include "shared/indirect_types.h"
#include "shared/photon_types.h"
#include "shared/vcm_types.h"
#include "stats/image_stats.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/log.h"

namespace clpt {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
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

// The image's metadata for `spp` samples after `seconds` of rendering (the final write and
// --save-every's).
ImageMetadata image_metadata(const Options& opt, const std::string& device, uint64_t spp, double seconds) {
  ImageMetadata meta;
  meta.strings = {{"Software", std::string("clpt ") + CLPT_VERSION},
                  {"clpt:integrator", opt.integrator},
                  {"clpt:device", device},
                  {"clpt:scene", opt.scene},
                  {"clpt:filter", opt.filter}};
  meta.ints = {{"clpt:spp", int(spp)}, {"clpt:seed", int(opt.seed)}, {"clpt:max_depth", int(opt.max_depth)}};
  meta.floats = {{"clpt:render_seconds", float(seconds)}, {"clpt:filter_radius", opt.filter_radius}};
  return meta;
}

}  // namespace

RenderSettings render_settings(const Options& opt) {
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
  settings.env_scale = opt.env_scale;
  settings.env_rotation = opt.env_rotate;
  settings.background = glm::vec3(opt.background[0], opt.background[1], opt.background[2]);
  settings.aperture = opt.aperture;
  settings.focus_distance = opt.focus_distance;
  settings.sampler = opt.sampler == "stratified" ? dev::SAMPLER_STRATIFIED
                     : opt.sampler == "lhs"      ? dev::SAMPLER_LHS
                     : opt.sampler == "sobol"    ? dev::SAMPLER_SOBOL
                                                 : dev::SAMPLER_INDEPENDENT;
  settings.filter = opt.filter == "tent"              ? dev::FILTER_TENT
                    : opt.filter == "gaussian"        ? dev::FILTER_GAUSSIAN
                    : opt.filter == "blackman-harris" ? dev::FILTER_BLACKMAN_HARRIS
                                                      : dev::FILTER_BOX;
  settings.filter_radius = opt.filter_radius > 0.0f ? opt.filter_radius : filter_default_radius(opt.filter);
  settings.mipmaps = opt.texture_filter == "trilinear";
  for (const std::string& a : opt.aovs) settings.aovs |= aov_bit(a);
  if (opt.aov_pfm) settings.aovs |= AOV_ALBEDO | AOV_NORMAL;
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
  settings.ao.radius = opt.ao_radius;
  if (!opt.bdpt_strategy.empty())
    parse_strategy(opt.bdpt_strategy, &settings.bdpt.strategy_s, &settings.bdpt.strategy_t);
  settings.bdpt.unweighted = opt.bdpt_unweighted;
  settings.bdpt.lvc = opt.bdpt_lvc;
  settings.bdpt.memory_bytes = size_t(opt.bdpt_memory_mib) << 20;
  settings.pm.photons = opt.photons;
  settings.pm.caustic_photons = opt.caustic_photons;
  settings.pm.final_gather = opt.final_gather;
  settings.pm.final_gather_cache = opt.final_gather_cache;
  settings.pm.knn = opt.knn;
  settings.pm.max_radius = opt.pm_max_radius;
  settings.pm.filter = opt.pm_filter == "box"            ? dev::PHOTON_FILTER_BOX
                       : opt.pm_filter == "epanechnikov" ? dev::PHOTON_FILTER_EPANECHNIKOV
                                                         : dev::PHOTON_FILTER_CONE;
  settings.sppm.photons = opt.photons;
  settings.sppm.radius = opt.sppm_radius;
  settings.sppm.alpha = opt.sppm_alpha;
  settings.mlt.multiplexed = opt.mlt_mode == "mmlt";
  settings.mlt.chains = opt.mlt_chains;
  settings.mlt.importance_tile = opt.mlt_target == "tile" ? kMltTile : 0u;
  settings.mlt.bootstrap = opt.mlt_bootstrap;
  settings.mlt.large_step = opt.mlt_large_step;
  settings.mlt.sigma = opt.mlt_sigma;
  settings.mlt.direct = opt.mlt_direct_ratio.value_or(kMltDirectAuto);
  settings.ic.error = opt.ic_error;
  settings.ic.rays = opt.ic_rays;
  settings.ic.min_spacing = opt.ic_min_spacing;
  settings.ic.max_spacing = opt.ic_max_spacing;
  settings.ic.gradients = !opt.ic_no_gradients;
  settings.ic.show_records = opt.ic_show_records;
  settings.ic.photons = opt.ic_photons;
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
  settings.vcm.pixel_radius = opt.vcm_shrink == "pixel";  // resolved by parse_options
  settings.vcm.shrink_given = opt.vcm_shrink_set;
  settings.vcm.merge_first = opt.vcm_merge == "first";
  settings.vcm.light_per_pixel = opt.vcm_light_paths;
  settings.vcm.alpha_given = opt.vcm_alpha_set;
  return settings;
}

RenderJob::RenderJob(const Options& opt, bool writes_image, const Cluster* cluster)
    : opt_(opt), writes_image_(writes_image), cluster_(cluster ? cluster : &alone_) {
  if (!writes_image_ && opt_.save_every > 0.0)
    throw Error(ExitCode::Usage, "--save-every rewrites the output: it needs one");
  if (!writes_image_ && opt_.aov_pfm)
    throw Error(ExitCode::Usage, "--aov-pfm writes its files beside the output: it needs one");
  {
    std::vector<NamedPath> outputs, inputs = {{"the scene", opt_.scene}};
    if (writes_image_) outputs.push_back({"output", opt_.output});
    if (opt_.aov_pfm)
      for (const std::string& pfm : aov_pfm_paths(opt_.output)) outputs.push_back({"--aov-pfm", pfm});
    if (opt_.stats && *opt_.stats != "-") outputs.push_back({"--stats", *opt_.stats});
    if (!opt_.checkpoint.empty()) outputs.push_back({"--checkpoint", opt_.checkpoint});
    if (!opt_.env.empty()) inputs.push_back({"--env", opt_.env});
    if (!opt_.reference.empty()) inputs.push_back({"--reference", opt_.reference});
    if (!opt_.resume.empty()) inputs.push_back({"--resume", opt_.resume});
    check_outputs_apart(outputs, inputs, {{"--checkpoint", "--resume"}});
  }
  if (writes_image_) check_output_path(opt_.output);
  if (opt_.aov_pfm)
    for (const std::string& pfm : aov_pfm_paths(opt_.output)) check_writable_path(pfm, "--aov-pfm");
  if (opt_.stats && *opt_.stats != "-") check_writable_path(*opt_.stats, "--stats");
  if (!opt_.checkpoint.empty()) check_writable_path(opt_.checkpoint, "--checkpoint");

  // A reference image's header is read before any work, so a bad one fails fast; its pixels
  // once the render's size is known and the header matches it (no allocation sized by an
  // unchecked header).
  if (!opt_.reference.empty()) {
    try {
      reference_size_ = read_image_size(opt_.reference, film_image_limits("no film is larger"));
    } catch (const Error& e) {
      throw Error(e.code(), std::string("--reference ") + e.what());
    }
  }
  LoadOptions load_options;
  load_options.lenient = opt_.lenient;
  for (const std::string& spec : opt_.limits) load_options.limits.set(spec);
  settings_ = render_settings(opt_);
  // The environment map, read whole before the scene and the device: a bad one fails fast,
  // and what a refused one costs is its own bytes, not the device's set-up as well.
  settings_.env_limits.max_dimension = load_options.limits.image_dimension;
  settings_.env_limits.max_pixels = load_options.limits.image_pixels;
  if (!opt_.env.empty()) {
    auto environment = std::make_shared<Environment>(
        load_environment(opt_.env, opt_.env_scale, opt_.env_rotate, settings_.env_limits));
    environment->background = settings_.background;
    settings_.environment = environment;
  }

  const auto t0 = Clock::now();
  scene_ = load_gltf(opt_.scene, load_options);
  load_seconds_ = seconds_since(t0);
  log::verbose("scene " + opt_.scene + ": " + std::to_string(scene_.triangles.size()) + " triangles, " +
               std::to_string(scene_.materials.size()) + " materials, " +
               std::to_string(scene_.cameras.size()) + " cameras, loaded in " +
               std::to_string(load_seconds_) + " s");

  devices_ = cl::select_devices(opt_.device);
  if ((devices_.size() > 1 || cluster_->size() > 1) && opt_.bdpt_mosaic)
    throw Error(ExitCode::Usage, "--bdpt-mosaic renders on one device; name one --device "
                                 "(and run one process)");
  std::vector<const cl::Context*> contexts;
  for (const cl::DeviceInfo& d : devices_) {
    log::verbose("device: " + d.label() + ", " + d.version + ", driver " + d.driver_version);
    contexts_.push_back(std::make_unique<cl::Context>(d));
    contexts.push_back(contexts_.back().get());
    device_names_ += (device_names_.empty() ? "" : ", ") + d.name;
  }
  if (opt_.bdpt_mosaic) return;  // each cell has its own renderer (app/bdpt_mosaic.h)

  // Problems of the scene the renderer finds (no triangles, a camera whose default image no
  // film holds) name the scene's file, as the loader's do.
  try {
    renderer_ = std::make_unique<Renderer>(contexts, scene_, settings_, cluster_);
  } catch (const Error& e) {
    if (e.code() != ExitCode::BadInput) throw;
    throw Error(ExitCode::BadInput, opt_.scene + ": " + e.what());
  }
  const uint32_t w = renderer_->width(), h = renderer_->height();
  if (reference_size_) {
    if (reference_size_->width != w || reference_size_->height != h)
      throw Error(ExitCode::Usage, "--reference " + opt_.reference + " is " +
                                       std::to_string(reference_size_->width) + "x" +
                                       std::to_string(reference_size_->height) + " but the render is " +
                                       std::to_string(w) + "x" + std::to_string(h) + " (use --resolution)");
    ImageLimits exact;
    exact.max_dimension = std::max(w, h);
    exact.max_pixels = uint64_t(w) * h;
    exact.raise = "the render's size";
    reference_ = read_image(opt_.reference, exact);
  }

  // Everything a checkpoint's sums depend on; a resume must match it exactly.
  std::error_code ec;
  signature_ = nlohmann::json{
      {"clpt", CLPT_VERSION},
      {"scene", std::filesystem::weakly_canonical(opt_.scene, ec).string()},
      {"triangles", scene_.triangles.size()},
      {"vertices", scene_.positions.size()},
      {"resolution", {w, h}},
      {"camera", opt_.camera},
      {"integrator", opt_.integrator},
      {"max_depth", opt_.max_depth},
      {"seed", opt_.seed},
      {"sampler", opt_.sampler},
      {"filter", {opt_.filter, opt_.filter_radius}},
      // Stratified and lhs divide each dimension into --spp strata: the total must match.
      {"strata", (opt_.sampler == "stratified" || opt_.sampler == "lhs") ? opt_.spp : 0},
      {"estimator", {opt_.direct, opt_.mis, opt_.light_samples, opt_.hemisphere, opt_.rr,
                     opt_.rr_depth, opt_.branching, opt_.ao_radius}}}.dump();
  if (!opt_.resume.empty()) {
    renderer_->restore(read_checkpoint(opt_.resume, signature_));
    log::info("resuming from " + opt_.resume);
  }
}

RenderJob::~RenderJob() = default;

JobResult RenderJob::run(const std::atomic<bool>* stop, const Progress& progress) {
  if (opt_.bdpt_mosaic) return run_mosaic(stop, progress);
  Renderer& renderer = *renderer_;
  const bool root = cluster_->root();  // rank 0 writes the files; the others only render
  const std::string processes =
      cluster_->size() > 1 ? " (rank 0 of " + std::to_string(cluster_->size()) + " processes)" : "";
  log::info("rendering " + opt_.scene + " at " + std::to_string(renderer.width()) + "x" +
            std::to_string(renderer.height()) + " with " + opt_.integrator + " on " + device_names_ +
            processes);
  double last_checkpoint = 0.0, last_save = 0.0, last_report = 0.0;
  const RenderOutput out = renderer.render(stop, [&](uint64_t done, uint64_t target, double t, bool last) {
    // With --reference, the relMSE so far, at most once a second (it reads the film back).
    std::string note;
    if (reference_ && t - last_report >= 1.0) {
      last_report = t;
      const FilmResult so_far = renderer.snapshot(done);  // collective: every rank reads its films
      if (root) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "relMSE %.4g", compare_images(so_far.mean, *reference_).rel_mse);
        note = buf;
      }
    }
    if (progress) progress(done, target, t, note);
    if (!opt_.checkpoint.empty() && !last && t - last_checkpoint >= opt_.checkpoint_interval) {
      last_checkpoint = t;
      const FilmState state = renderer.film_state(done);
      if (root) write_checkpoint(opt_.checkpoint, signature_, state);
    }
    // --save-every: the image so far, written as the final one is (temporary file, rename), so a
    // viewer that reloads never sees half a file; not after the last pass, which the final
    // write follows at once.
    if (opt_.save_every > 0.0 && !last && done > 0 && t - last_save >= opt_.save_every) {
      last_save = t;
      ImageMetadata meta = image_metadata(opt_, device_names_, done, t);
      const DisplaySettings display = display_settings(opt_, &meta);
      const FilmResult so_far = renderer.snapshot(done);
      if (root) write_image(opt_.output, so_far.mean, meta, {}, display);
      log::verbose("saved " + std::to_string(done) + " spp to " + opt_.output);
    }
  });

  const FilmResult& film = out.film;
  const RenderStats& st = out.stats;
  if (!opt_.checkpoint.empty() && film.samples_per_pixel > 0) {
    const FilmState state = renderer.film_state(film.samples_per_pixel);
    if (root) write_checkpoint(opt_.checkpoint, signature_, state);
  }

  JobResult r;
  r.image = film.mean;
  r.samples_per_pixel = film.samples_per_pixel;
  r.interrupted = out.interrupted;
  r.metadata = image_metadata(opt_, device_names_, film.samples_per_pixel, st.render_seconds);
  r.display = display_settings(opt_, &r.metadata);
  if (film.variance_available && film.samples_per_pixel > 0)
    r.variance = variance_of_mean(film.variance, film.samples_per_pixel);
  if (opt_.variance && r.variance) r.layers.push_back({kVarianceLayer, *r.variance});
  if (opt_.vcm_merged)
    for (const NamedChannel& l : out.layers)
      if (l.name == "merged") r.layers.push_back(l);
  // --aov's layers in the order named (variance is above); --aov-pfm's albedo and normal ride
  // along in r.aovs without becoming layers unless named.
  r.aovs = out.aovs;
  for (const std::string& a : opt_.aovs) {
    const uint32_t bit = aov_bit(a);  // 0 for variance, added above
    for (const NamedChannel& l : out.aovs)
      if (bit && l.name == aov_layer_name(bit)) r.layers.push_back(l);
  }
  r.stats = stats_document(opt_, devices_.front(), out, renderer.width(), renderer.height(), load_seconds_,
                           reference_ ? &*reference_ : nullptr);

  const double paths = double(film.samples_per_pixel) * renderer.width() * renderer.height();
  const double secs = st.render_seconds > 0.0 ? st.render_seconds : 1e-9;
  const IntegratorInfo& row = integrator_info(opt_.integrator);
  log::info((out.interrupted ? "interrupted: " : "") + std::string("rendered ") +
            std::to_string(film.samples_per_pixel) + " spp in " + std::to_string(st.render_seconds) +
            " s (" + std::to_string(paths / secs / 1e6) +
            (row.traces_light_paths ? " M light paths/s)"
             : row.options & OPTIONS_MLT ? " M mutations/s)"
                                         : " M camera paths/s)"));
  if (film.dropped_samples) log::warn(std::to_string(film.dropped_samples) + " NaN/Inf samples were dropped");
  return r;
}

// --bdpt-mosaic: the strategies of bdpt as one image (app/bdpt_mosaic.h).
JobResult RenderJob::run_mosaic(const std::atomic<bool>* stop, const Progress& progress) {
  log::info("rendering the bdpt strategy mosaic of " + opt_.scene + " on " + device_names_);
  const auto start = Clock::now();
  const MosaicResult m = render_bdpt_mosaic(
      *contexts_.front(), scene_, settings_, opt_.bdpt_unweighted, stop, [&](uint32_t done, uint32_t total) {
        if (progress) progress(done, total, seconds_since(start), "strategies");
      });
  JobResult r;
  r.image = m.image;
  r.samples_per_pixel = m.cells_rendered ? m.samples_per_pixel : 0;
  r.interrupted = m.interrupted;
  r.metadata.strings = {{"Software", std::string("clpt ") + CLPT_VERSION},
                        {"clpt:integrator", "bdpt"},
                        {"clpt:bdpt_mosaic", opt_.bdpt_unweighted ? "unweighted" : "weighted"},
                        {"clpt:device", device_names_},
                        {"clpt:scene", opt_.scene}};
  r.metadata.ints = {{"clpt:spp", int(m.samples_per_pixel)}, {"clpt:seed", int(opt_.seed)}};
  r.display = display_settings(opt_, &r.metadata);
  log::info((m.interrupted ? "interrupted: " : "") + std::to_string(m.cells_rendered) + " of " +
            std::to_string(m.cells_total) + " strategies at " + std::to_string(m.samples_per_pixel) +
            " spp (rows: 0 to 4 bounces; columns: S = 0, 1, ...)");
  return r;
}

std::vector<std::string> aov_pfm_paths(const std::string& output) {
  const std::filesystem::path p(output);
  const std::string stem = (p.parent_path() / p.stem()).string();
  return {stem + ".color.pfm", stem + ".albedo.pfm", stem + ".normal.pfm"};
}

void write_job_image(const Options& opt, const JobResult& result) {
  if (result.samples_per_pixel == 0) {
    log::warn("no sample was taken; " + opt.output + " was not written");
    return;
  }
  write_image(opt.output, result.image, result.metadata, result.layers, result.display);
  log::info("wrote " + opt.output);
  if (opt.aov_pfm) {
    const std::vector<std::string> pfm = aov_pfm_paths(opt.output);
    write_pfm(pfm[0], result.image);
    for (const NamedChannel& l : result.aovs) {
      if (l.name == aov_layer_name(AOV_ALBEDO)) write_pfm(pfm[1], l.image);
      if (l.name == aov_layer_name(AOV_NORMAL)) write_pfm(pfm[2], l.image);
    }
    log::info("wrote " + pfm[0] + ", " + pfm[1] + ", " + pfm[2] + " (oidnDenoise --hdr " + pfm[0] +
              " --alb " + pfm[1] + " --nrm " + pfm[2] + " -o denoised.pfm)");
  }
}

void write_job_stats(const std::string& where, const nlohmann::json& stats) {
  const std::string text = stats.dump(2) + "\n";
  if (where == "-") {
    std::cout << text << std::flush;
    return;
  }
  std::string why;
  if (!write_file_atomically(where, [&](std::ostream& out) { out << text; }, &why))
    throw Error(ExitCode::Output, "cannot write statistics to " + where);
}

}  // namespace clpt
