#include "app/stats_document.h"

#include <sys/resource.h>

#include "integrators/integrator.h"
#include "shared/indirect_types.h"
#include "shared/photon_types.h"
#include "shared/vcm_types.h"
#include "stats/image_stats.h"

namespace clpt {
namespace {

double peak_rss_mib() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

nlohmann::json stats_document(const Options& opt, const cl::DeviceInfo& device, const RenderOutput& out,
                              uint32_t width, uint32_t height, double load_seconds,
                              const Image* reference) {
  const FilmResult& film = out.film;
  const RenderStats& st = out.stats;
  const double paths = double(film.samples_per_pixel) * width * height;
  const double secs = st.render_seconds > 0.0 ? st.render_seconds : 1e-9;
  nlohmann::json j;
  j["scene"] = opt.scene;
  j["integrator"] = opt.integrator;
  j["device"] = {{"name", device.name},           {"platform", device.platform_name},
                 {"version", device.version},     {"driver", device.driver_version},
                 {"compute_units", device.compute_units}};
  // Every device's share (one entry with one device): samples per pixel and the paths per
  // second of its own passes (launch to finish).
  j["devices"] = nlohmann::json::array();
  for (const DeviceShare& d : st.devices)
    j["devices"].push_back({{"name", d.name},
                            {"device", d.label},
                            {"samples_per_pixel", d.samples},
                            {"passes", d.passes},
                            {"busy_seconds", d.busy_seconds},
                            {"paths_per_second", d.busy_seconds > 0.0
                                                     ? double(d.samples) * width * height / d.busy_seconds
                                                     : 0.0}});
  j["resolution"] = {width, height};
  j["triangles"] = st.triangles;
  j["emitters"] = st.emitters;
  j["lights"] = st.lights;
  j["scene_load_seconds"] = load_seconds;
  j["bvh"] = {{"build_seconds", st.bvh_build_seconds},
              {"max_leaf", st.bvh_max_leaf},
              {"nodes", st.bvh_nodes},
              {"depth", st.bvh_depth},
              {"wide_nodes", st.bvh_wide_nodes},
              {"wide_depth", st.bvh_wide_depth}};
  j["kernel"] = {{"seconds", st.kernel_seconds}, {"from_cache", st.kernel_from_cache}};
  j["render_seconds"] = st.render_seconds;
  j["film_gather_seconds"] = st.film_gather_seconds;
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
                {"b_bootstrap", m.b_bootstrap},
                {"b_large_steps", m.b_large_steps},
                {"restarts", m.restarts},
                {"mutations", proposed},
                {"mutations_per_second", double(proposed) / secs},
                {"large_step_acceptance", rate(m.large_accepted, m.large_proposed)},
                {"small_step_acceptance", rate(m.small_accepted, m.small_proposed)},
                {"acceptance", rate(m.large_accepted + m.small_accepted, proposed)},
                {"device_bytes", m.device_bytes}};
    j["mlt"]["direct_ratio"] = m.direct_ratio;
    j["mlt"]["direct_samples"] = m.direct_samples;
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
                {"alpha", v.alpha},
                {"shrink", v.pixel_radii ? "pixel" : "pass"},
                {"merge", v.merge_first ? "first" : "all"},
                {"light_paths_per_pixel", v.light_per_pixel},
                {"light_vertices", v.light_vertices},
                {"connections", v.connections},
                {"connections_per_second", double(v.connections) / secs},
                {"merges", v.merges},
                {"merges_per_second", double(v.merges) / secs},
                {"grids", v.grids},
                {"grid_seconds", v.grid_seconds},
                {"device_bytes", v.device_bytes}};
    // --vcm-light-paths auto: its pilot's figures per candidate K (an empty list where none
    // ran: a render too short for one, or one that ended first).
    if (v.light_paths_auto) {
      nlohmann::json candidates = nlohmann::json::array();
      for (const LightPathPilot::Candidate& c : v.pilot)
        candidates.push_back({{"k", c.k},
                              {"passes", c.passes},
                              {"seconds_per_pass", c.passes ? c.seconds / c.passes : 0.0},
                              {"relative_variance", c.relative_variance},
                              {"relmse_seconds", c.cost}});
      // After the pilot the last pass's K is its choice.
      j["vcm"]["light_paths_auto"] = {
          {"chosen", v.pilot.empty() ? nlohmann::json() : nlohmann::json(v.light_per_pixel)},
          {"candidates", candidates}};
    } else {
      j["vcm"]["light_paths_auto"] = nullptr;
    }
    if (v.pixel_radius_count)
      j["vcm"]["pixel_radius"] = {{"min", v.pixel_radius_min},
                                  {"mean", v.pixel_radius_sum / double(v.pixel_radius_count)},
                                  {"max", v.pixel_radius_max}};
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
  j["filter"] = {{"name", opt.filter}, {"radius", opt.filter_radius}};
  j["estimator"] = {{"sampler", opt.sampler},       {"direct", opt.direct},
                    {"mis", opt.mis},               {"light_samples", opt.light_samples},
                    {"hemisphere", opt.hemisphere}, {"rr", opt.rr},
                    {"rr_depth", opt.rr_depth},     {"branching", opt.branching}};
  j["interrupted"] = out.interrupted;
  // Per triangle: the geometry's share (BVH, triangles, vertices, lights), textures apart.
  j["memory"] = {{"scene_device_bytes", st.scene_device_bytes},
                 {"texture_device_bytes", st.texture_device_bytes},
                 {"texture_mip_bytes", st.texture_mip_bytes},
                 {"scene_device_bytes_per_triangle",
                  st.triangles ? double(st.scene_device_bytes - st.texture_device_bytes) /
                                     double(st.triangles)
                               : 0.0},
                 {"film_device_bytes", st.film_device_bytes},
                 {"peak_host_rss_mib", peak_rss_mib()}};
  return j;
}

}  // namespace clpt
