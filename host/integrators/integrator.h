// An integrator owns its kernels and renders in passes: each pass adds
// `samples` samples per pixel, starting at sample index `first_sample`, to the film.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "cl/program.h"
#include "integrators/vcm_pilot.h"
#include "io/image_io.h"
#include "render/film.h"
#include "render/scene_buffers.h"
#include "shared/bdpt_types.h"
#include "shared/photon_types.h"
#include "shared/render_types.h"

namespace clpt {

// Photon figures of pm and sppm for --stats (zero for the other integrators).
struct PhotonStats {
  uint64_t paths = 0;             // photon paths emitted (all maps, all passes)
  uint64_t stored = 0;            // photons stored
  uint64_t rays = 0;              // rays the photon paths traced
  double emit_seconds = 0.0;      // photon tracing, device
  double build_seconds = 0.0;     // pm: kd-tree builds (host); sppm: hashed grid builds (device)
  uint64_t builds = 0;            // pm: maps built; sppm: grids built (one per pass)
  size_t device_bytes = 0;        // photon, tree and grid buffers on the device at the end
};

// Metropolis figures of mlt for --stats.
struct MetropolisStats {
  // Another device's chains added: chains and their proposals summed; the bootstrap (b, its
  // paths and time) is alike on every device, and this one's is kept, as its device_bytes
  // (memory figures are one device's).
  void add_chains(const MetropolisStats& other);
  uint32_t chains = 0;
  uint32_t dims = 0;               // coordinates of a chain's primary sample vector
  uint64_t bootstrap_paths = 0;
  double b = 0.0;                  // normalisation: the mean target (luminance) of the
  double b_standard_error = 0.0;   //   bootstrap's paths and the large steps' proposals;
                                   //   mmlt: the sum over path lengths of theirs
  std::vector<double> b_by_depth;  // mmlt: each path length's (bounces 0, 1, ...) ...
  std::vector<double> b_depth_standard_error;  // ... and its standard error
  double b_bootstrap = 0.0;        // b from the bootstrap alone (the first segment's)
  uint64_t b_large_steps = 0;      // large steps' proposals counted into b
  uint32_t restarts = 0;           // path lengths whose chains restarted from their pools
  std::vector<uint32_t> chains_by_depth;
  // mmlt with the direct light rendered apart (--mlt-direct): its samples per pixel for every
  // mutation per pixel, and the samples per pixel it took (every device's together); the
  // chains then sample bounces 2 on. 0 and 0: the chains sample the direct light too.
  double direct_ratio = 0.0;
  uint64_t direct_samples = 0;
  double bootstrap_seconds = 0.0;
  uint64_t large_proposed = 0, large_accepted = 0;
  uint64_t small_proposed = 0, small_accepted = 0;
  size_t device_bytes = 0;         // chain states and their vectors
};

// Irradiance cache figures of ic for --stats.
struct IcStats {
  // Another device's image samples added (lookups, records used, misses); the cache is built
  // alike on every device, and this one's figures are kept.
  void add_lookups(const IcStats& other);
  uint64_t records = 0;
  uint32_t rays_per_record = 0;     // M x N hemisphere rays
  uint32_t placement_passes = 0;    // grid levels, coarse to fine
  uint32_t refinements = 0;         // rounds of --ic-rays more rays for every record
  uint64_t candidates = 0;          // uncovered points the placement found (before thinning)
  double build_seconds = 0.0;       // placement, records and grids, device and host
  double record_seconds = 0.0;      // of which the records' hemisphere rays and sums
  uint64_t lookups = 0;             // image samples that read the cache
  uint64_t records_used = 0;        // records those lookups interpolated, in all
  uint64_t misses = 0;              // lookups no record covered (path traced instead)
  size_t device_bytes = 0;          // records, grid and the record rays' results
};

// Vertex connection and merging figures of vcm for --stats.
struct VcmStats {
  // Another device's figures added: counts and times summed, the radii's range widened.
  void add(const VcmStats& other);
  uint64_t light_vertices = 0;    // stored (all passes)
  uint64_t connections = 0;       // shadow rays of connection strategies (NEE, t = 1, s, t >= 2)
  uint64_t merges = 0;            // light vertices merged at camera vertices
  uint32_t passes = 0;            // one merge radius each
  uint32_t tiles = 0;             // per pass (the light vertex buffer's budget)
  uint64_t grids = 0;             // grids built
  double grid_seconds = 0.0;      // building them (device)
  float first_radius = 0.0f, last_radius = 0.0f;
  float alpha = 0.0f;             // the shrink's (as the renderer resolved it)
  uint32_t pixel_radii = 0;       // 1: per-pixel radii (--vcm-shrink pixel), 0: the pass rule
  uint32_t merge_first = 0;       // 1: merges at the first non-delta camera vertex only
  uint32_t light_per_pixel = 0;   // light subpaths per pixel of the last pass (auto's choice after its pilot)
  uint32_t light_paths_auto = 0;  // 1: --vcm-light-paths auto
  // --vcm-light-paths auto: the pilot's figures per candidate K (none: K was given, the
  // render was too short for a pilot, or it ended before the pilot did).
  std::vector<LightPathPilot::Candidate> pilot;
  // --vcm-shrink pixel: the pixels' radii after the last pass (count 0: not kept per pixel).
  float pixel_radius_min = 0.0f, pixel_radius_max = 0.0f;
  double pixel_radius_sum = 0.0;
  uint64_t pixel_radius_count = 0;
  size_t device_bytes = 0;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual const char* name() const = 0;
  // Launches every kernel once over no work, so drivers that compile at the first launch
  // (PoCL) do it at start-up and not in the first timed pass. Leaves the film as it was.
  virtual void warm_up(const dev::RenderParams& params, Film& film) = 0;
  // Enqueues one pass of params.samples_per_pass (> 0) samples; it completes by the next
  // blocking call on the queue (film read, finish).
  virtual void render_pass(const dev::RenderParams& params, Film& film) = 0;
  // Start-up work that every device of a render would otherwise do alike before its first
  // pass (mlt's bootstrap paths), shared out instead: the renderer gives each device of every
  // rank a range [first, first + count) of the setup_items() items, runs setup_part on it (its
  // results as bytes), and hands every device the parts of all devices, concatenated in
  // device and rank order (the items' order), in setup_finish. With no items (the default),
  // none of this happens. The film is the one the passes render into.
  virtual uint64_t setup_items(const dev::RenderParams& params) const {
    (void)params;
    return 0;
  }
  virtual std::string setup_part(const dev::RenderParams& params, Film& film, uint64_t first,
                                 uint64_t count) {
    (void)params, (void)film, (void)first, (void)count;
    return {};
  }
  virtual void setup_finish(const dev::RenderParams& params, Film& film, const std::string& parts) {
    (void)params, (void)film, (void)parts;
  }
  // Whether the image is the same however the samples are split into passes (each sample
  // is a function of its index alone). Metropolis is not: a pass runs whole mutations per
  // chain, so the renderer gives it a schedule that does not look at the clock.
  virtual bool pass_invariant() const { return true; }
  // How its program was obtained (cache or build) and how long that took.
  virtual const cl::BuildInfo& build_info() const = 0;
  // Shadow rays of connection strategies so far (bdpt); 0 for integrators without them.
  virtual uint64_t connections() const { return 0; }
  virtual PhotonStats photon_stats() const { return {}; }
  virtual MetropolisStats metropolis_stats() const { return {}; }
  virtual IcStats ic_stats() const { return {}; }
  virtual VcmStats vcm_stats() const { return {}; }
  // Extra images an integrator offers beside the film's (vcm: "merged", the part of the image
  // merging contributed), as means over `spp` samples per pixel; none by default.
  virtual std::vector<NamedChannel> layers(uint64_t spp) const {
    (void)spp;
    return {};
  }
  // The renderer's stop flag (Ctrl-C), for integrators whose passes include work longer than
  // a pass (ic's cache refinement under --time) to end that work early; null: none.
  void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }
  // This device's place among every device of the render, every rank's (0: the first, and
  // the only one of a one-device render), set before the first pass: what keeps the devices
  // of an integrator that splits by chains (DeviceSplit::Chains) from repeating each other.
  void set_device_index(uint32_t index) { device_index_ = index; }

 protected:
  bool stop_requested() const { return stop_ && stop_->load(); }
  const std::atomic<bool>* stop_flag() const { return stop_; }
  uint32_t device_index() const { return device_index_; }

 private:
  const std::atomic<bool>* stop_ = nullptr;
  uint32_t device_index_ = 0;
};

// params with no samples per pass: a launch where every work-item loops over nothing, which
// is how the one-kernel integrators warm up.
inline dev::RenderParams without_samples(const dev::RenderParams& params) {
  dev::RenderParams none = params;
  none.samples_per_pass = 0;
  return none;
}

// The tile target's tiles (--mlt-target tile): kMltTile x kMltTile pixels.
constexpr uint32_t kMltTile = 8;

// --mlt-direct auto (MltConfig::direct).
constexpr float kMltDirectAuto = -1.0f;

// mlt's settings (--mlt-*).
struct MltConfig {
  bool multiplexed = true;   // --mlt-mode mmlt (over bdpt's strategies); false: pssmlt (over pt)
  uint32_t chains = 0;       // 0: Metropolis::default_chains
  uint32_t bootstrap = 100000;  // pssmlt: paths; mmlt: paths per path length
  float large_step = 0.3f;   // probability of a large step
  float sigma = 0.01f;       // small steps' standard deviation
  // --mlt-target: 8 (tile): the target is luminance times the image's mean over its 8 x 8
  // tile's mean (Metropolis::tile_importance); 0 (luminance): luminance alone.
  uint32_t importance_tile = kMltTile;
  // false: chain c starts at bootstrap path c instead of one drawn in proportion to its
  // target, which is the start-up bias the resampling removes (tests show it; no option).
  bool resample = true;
  // false: the chains never restart from their large steps' pools, and b stays the
  // bootstrap's for the whole render (its error then never fades; tests show it; no option).
  bool restart = true;
  // --mlt-direct: the direct light (bounces 0 and 1) rendered apart by pt_render, this many
  // samples per pixel for every mutation per pixel, the chains sampling bounces 2 on; 0: the
  // chains sample it too; kMltDirectAuto: its share of the chains' target, from the bootstrap
  // for mmlt (Metropolis::direct_ratio), from the first direct samples for pssmlt
  // (Metropolis::direct_share).
  float direct = kMltDirectAuto;
};

// ic's settings (--ic-*).
struct IcConfig {
  float error = 0.2f;         // a: Ward's accuracy, eps_i < a
  float min_spacing = 1.5f;   // a record's validity radius a R_i, in pixel footprints: at least
  float max_spacing = 32.0f;  //   ... and at most
  uint32_t rays = 256;        // hemisphere rays per record (M x N, M = round(sqrt(rays / pi)))
  bool gradients = true;      // extrapolate with Ward and Heckbert's gradients
  bool show_records = false;  // pixels that placed a record render red
  // ic: global photon map paths whose density estimates the records' rays read where they
  // land (--ic-photons); 0: the rays are path traced. pm --final-gather-cache reads pm's map.
  uint64_t photons = 0;
  // Seconds the cache may spend refining its records (another --ic-rays per record per
  // round) after placement; kIcRefineShare of --time (make_ic), 0 without.
  double refine_seconds = 0.0;
};

// The share of --time the irradiance cache spends refining its records.
constexpr double kIcRefineShare = 0.25;

// vcm's --vcm-alpha defaults for its two shrink rules (the sweeps of docs/BENCHMARKS.md; per
// pixel sppm's 2/3 since vcm merges at the first vertex alone, session 33).
constexpr float kVcmPixelAlpha = 2.0f / 3.0f, kVcmPassAlpha = 0.75f;

// vcm's settings (--vcm-*).
struct VcmConfig {
  uint32_t mode = 0;        // dev::VcmMode (--vcm-mode)
  float radius = 0.0f;      // the first pass's merge radius; 0: half default_merge_radius
  // The defaults are the command line's with the box filter (parse_options resolves them).
  float alpha = kVcmPixelAlpha;  // per pixel sppm's shrink; per pass radius_i = radius (i + 1)^((alpha - 1) / 2)
  bool pixel_radius = true;  // --vcm-shrink pixel: each pixel's radius, shrunk by its merges
  bool merge_first = true;  // --vcm-merge first: merging at the first non-delta camera vertex only
  // --vcm-light-paths: light subpaths per pixel and pass; 0: auto, chosen by the first
  // passes' measured efficiency (integrators/vcm_pilot.h)
  uint32_t light_per_pixel = 0;
  // The passes the render plans (its --spp when that ends it, 0: --time does): auto takes
  // K = 1 without a pilot in a render too short for one.
  uint64_t planned_passes = 0;
  // Whether the command line named the rule and alpha (else the renderer may choose: the pass
  // rule with its own alpha when the passes are split over devices or ranks).
  bool shrink_given = false, alpha_given = false;
};

// The scene's lengths the integrators' default radii are measured in (the renderer's).
struct SceneScale {
  float diagonal = 1.0f;         // of the scene's bounding box
  float pixel_footprint = 0.0f;  // a pixel's width at the scene's centre (render/camera_setup.h);
                                 // 0 or not finite where the camera gives none
};

// bdpt's settings (--bdpt-*); vcm's light subpaths take lvc and memory_bytes too.
struct BdptConfig {
  uint32_t strategy_s = BDPT_ALL_STRATEGIES;  // --bdpt-strategy s,t: the one strategy that
  uint32_t strategy_t = 0;                    //   contributes; BDPT_ALL_STRATEGIES: every one
  bool unweighted = false;                    // --bdpt-unweighted: that strategy without its weight
  uint32_t lvc = 0;                           // --bdpt-lvc: light vertex caching's connections
  size_t memory_bytes = size_t(256) << 20;    // --bdpt-memory: light vertex buffer budget
};

// pm's settings (--photons, --caustic-photons, --final-gather*, --knn, --pm-*).
struct PmConfig {
  uint64_t photons = 0;                 // global map paths; 0: PhotonMapper::kDefaultGlobalPaths
  uint64_t caustic_photons = 1000000;   // caustic map paths
  uint32_t final_gather = 8;            // gather rays per sample; 0: the global map at the hit
  bool final_gather_cache = false;      // the final gather's diffuse part from an irradiance cache
  uint32_t knn = 50;                    // photons per estimate
  float max_radius = 0.0f;              // 0: 2 % of the scene's diagonal
  uint32_t filter = dev::PHOTON_FILTER_CONE;
};

// How pm's estimates read a photon map (also what ic's records read with --ic-photons):
// --knn clamped to the kernels' heap, the maximum radius's default resolved.
dev::PhotonLookup photon_lookup(const PmConfig& pm, const SceneScale& scale);

// sppm's settings (--photons, --sppm-*).
struct SppmConfig {
  uint64_t photons = 0;          // photon paths per pass; 0: one per pixel
  float radius = 0.0f;           // initial radius; 0: default_merge_radius
  float alpha = 2.0f / 3.0f;     // fraction of each pass's photons kept
};

// The radius sppm starts from by default (and, halved, vcm's): two pixel footprints at the
// scene's centre, or 1e-3 of the diagonal where the camera gives no footprint.
float default_merge_radius(const SceneScale& scale);

// ao's settings (--ao-radius).
struct AoConfig {
  float radius = 0.0f;  // occluders farther away do not count; 0: 10 % of the scene's diagonal
};

// What the integrators are made from: each one's settings, and what their defaults need.
struct IntegratorConfig {
  BdptConfig bdpt;
  PmConfig pm;
  SppmConfig sppm;
  AoConfig ao;
  MltConfig mlt;
  IcConfig ic;
  VcmConfig vcm;
  uint32_t indirect = 0;    // indirect1: dev::IndirectGenerator (--indirect)
  SceneScale scale;
  double time_limit = 0.0;  // --time; ic refines its records for kIcRefineShare of it
};

// What an integrator's film holds, which decides what the film and the command line offer.
enum class FilmKind {
  SampleSums,   // sums of independent samples per pixel: per-pixel variance, checkpoints
  Splats,       // light paths splat into any pixel (lt, bdpt): neither
  Progressive,  // progressive estimates with per-pixel state (sppm): neither
};

// Option groups that only some integrators read (--help names them after the integrator).
enum IntegratorOptions : unsigned {
  OPTIONS_NONE = 0,
  OPTIONS_PHOTONS = 1u << 0,  // --photons
  OPTIONS_PM = 1u << 1,       // --caustic-photons, --final-gather, --knn, --pm-max-radius, --pm-filter
  OPTIONS_SPPM = 1u << 2,     // --sppm-radius, --sppm-alpha
  OPTIONS_BDPT = 1u << 3,     // --bdpt-strategy, --bdpt-unweighted, --bdpt-mosaic
  OPTIONS_AO = 1u << 4,       // --ao-radius
  OPTIONS_MLT = 1u << 5,      // --mlt-mode, --mlt-target, --mlt-large-step, --mlt-sigma, --mlt-bootstrap, --mlt-chains
  OPTIONS_IC = 1u << 6,       // --ic-error, --ic-rays, --ic-min-spacing, --ic-max-spacing, --ic-no-gradients, --ic-show-records, --ic-photons
  OPTIONS_VCM = 1u << 7,      // --vcm-mode, --vcm-radius, --vcm-alpha, --vcm-merged
  OPTIONS_LVC = 1u << 8,      // --bdpt-lvc (light vertex caching: bdpt and vcm)
  OPTIONS_INDIRECT = 1u << 9, // --indirect
};

// How an integrator's render is shared by several devices (--device A,B) and MPI ranks.
enum class DeviceSplit {
  // It is not: each pass depends on every pass before it (sppm's per-pixel radii and photon
  // counts), so it renders on one device and one process.
  OneDevice,
  // Disjoint sample ranges, each sample a function of its index alone: the image equals one
  // device's up to the rounding of the film's sums. What a pass reads besides is built alike
  // from the seed on every device (pm's maps, ic's cache, pm's final-gather cache); vcm's
  // radius follows the sample index.
  Samples,
  // Each device runs chains of its own (mlt), keyed by its device index, all from the same
  // bootstrap: their mutations add up to the render's, and the image is one estimate with
  // more chains, equal to one device's in expectation, not sample for sample.
  Chains,
};

// One row per integrator --integrator accepts: everything the options, the renderer, the
// statistics and the checks need to know about it. A new integrator is one row here (and
// its class and kernels).
struct IntegratorInfo {
  const char* name;
  bool implemented;
  FilmKind film;
  unsigned options;              // IntegratorOptions it reads
  bool needs_lights;             // false: renders without lights (ao)
  bool needs_perspective_camera; // light paths cannot reach an orthographic camera
  uint32_t max_depth_cap;        // 0: none; direct: 1; indirect1: 2
  bool traces_light_paths;       // its paths per second count light paths (lt), not camera paths
  // How it renders on several devices (--device A,B, MPI ranks); DeviceSplit says.
  DeviceSplit split;
  std::unique_ptr<Integrator> (*make)(const cl::Context&, const SceneBuffers&,
                                      const IntegratorConfig&);  // null: not implemented
};

// Every row, in --help order.
const std::vector<IntegratorInfo>& integrator_table();
// The row of `name`, or null when --integrator does not know it.
const IntegratorInfo* find_integrator(const std::string& name);
// The row of `name`; throws Error(Usage) for an unknown one.
const IntegratorInfo& integrator_info(const std::string& name);
// "pt|lt|..." of every row, and "pt, lt, ..." of the implemented ones.
std::string integrator_names_text(const char* separator, bool implemented_only);

// Throws Error(Usage) for an unknown or not yet implemented name.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const cl::Context& ctx,
                                            const SceneBuffers& scene,
                                            const IntegratorConfig& config = {});

}  // namespace clpt
