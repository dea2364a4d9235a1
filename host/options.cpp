#include "options.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <iostream>
#include <sstream>

#include "integrators/integrator.h"
#include "io/image.h"
#include "scene/load_limits.h"
#include "util/error.h"

namespace clpt {
namespace {

// Every real-valued option: NaN, infinities and numbers past the type's range are refused
// with the option's name (CLI11's own range checks let NaN through: every comparison with it
// is false). A text that is not a number at all is left to the option's conversion.
const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);  // overflow gives +-HUGE_VAL: infinite
      if (end == text.c_str()) return std::string();
      if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
        return text + " is not a finite number";
      return std::string();
    },
    "", "finite");

struct Parser {
  CLI::App app{"clpt: an OpenCL physically based renderer for glTF 2.0 scenes.", "clpt"};
  Options o;
  std::string resolution;
  std::string stats_value;
  std::string background;
  CLI::Option* spp_opt = nullptr;
  CLI::Option* time_opt = nullptr;
  CLI::Option* stats_opt = nullptr;

  Parser() {
    app.set_version_flag("--version", std::string("clpt ") + CLPT_VERSION);
    app.get_formatter()->column_width(30);
    app.add_option("scene", o.scene, "glTF 2.0 scene to render (.gltf or .glb)")->type_name("FILE");
    app.add_option("-o,--output", o.output,
                   "Output image: .exr (linear float) or .png/.jpg (sRGB, through --view) [clpt.exr]")
        ->type_name("FILE");
    app.add_option("--view", o.view,
                   "How .png/.jpg show radiance: standard (clamp), khronos-neutral, agx, aces [standard]")
        ->type_name("NAME")
        ->check(CLI::IsMember({"standard", "khronos-neutral", "agx", "aces"}).description(""));
    app.add_option("--exposure", o.exposure, "Exposure in stops before --view; .exr stays unscaled [0]")
        ->type_name("EV")
        ->check(kFinite);
    app.add_option("--save-every", o.save_every,
                   "Also write the output every SECONDS while rendering, atomically, for viewers that reload")
        ->type_name("SECONDS")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--device", o.device,
                   "OpenCL device: pocl, gpu, cpu, PLATFORM:DEVICE, or a name substring "
                   "[first GPU, else PoCL]; several, comma-separated, or all (every GPU, else "
                   "every device) share the samples; under mpirun, rank: one GPU per rank on "
                   "each node")
        ->type_name("SPEC");
    app.add_flag("--list-devices", o.list_devices, "List OpenCL devices and exit");
    spp_opt = app.add_option("--spp", o.spp, "Samples per pixel [64; unlimited with --time alone]")
                  ->type_name("N")
                  ->check(CLI::Range(uint64_t(1), uint64_t(0xffffffffu)).description(""));
    time_opt = app.add_option("--time", o.time_limit,
                              "Time budget in seconds; with --spp, whichever ends first")
                   ->type_name("SECONDS")
                   ->check(CLI::PositiveNumber.description(""))
                   ->check(kFinite);
    app.add_option("--pass-seconds", o.pass_seconds,
                   "Length a pass of samples aims at (progress, Ctrl-C and --time act between passes) "
                   "[0.1; 0.03 on GPUs]")
        ->type_name("SECONDS")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--resolution", resolution, "Image size WxH [640 wide, camera aspect]")
        ->type_name("WxH");
    app.add_option("--camera", o.camera,
                   "Camera index or name [the file's first camera, else one framing the scene]")
        ->type_name("CAMERA");
    app.add_option("--aperture", o.aperture,
                   "Thin-lens aperture radius in scene units; 0 is a pinhole [0]")
        ->type_name("RADIUS")
        ->check(CLI::NonNegativeNumber.description(""))
        ->check(kFinite);
    app.add_option("--focus-distance", o.focus_distance,
                   "Distance in focus with --aperture [to the scene's centre along the view]")
        ->type_name("DIST")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--env", o.env,
                   "Environment map, equirectangular .hdr/.exr, +y up, image centre towards -z")
        ->type_name("FILE");
    app.add_option("--env-scale", o.env_scale, "Multiplies the environment map's radiance [1]")
        ->type_name("S")
        ->check(CLI::NonNegativeNumber.description(""))
        ->check(kFinite);
    app.add_option("--env-rotate", o.env_rotate, "Turns the environment about +y [0]")
        ->type_name("DEGREES")
        ->check(kFinite);
    app.add_option("--background", background,
                   "Constant radiance of rays that escape, without --env [0,0,0]")
        ->type_name("R,G,B");
    app.add_option("--max-depth", o.max_depth, "Maximum bounces; 0 shows emitters only [8]")
        ->type_name("N")
        ->check(CLI::Range(0u, 1024u).description(""));
    app.add_option("--seed", o.seed, "Random seed [0]")->type_name("N");
    app.add_option("--integrator", o.integrator,
                   "Integrator: " + integrator_names_text("|", false) +
                       " (implemented: " + integrator_names_text(", ", true) + ") [pt]")
        ->type_name("NAME");
    app.add_option("--sampler", o.sampler,
                   "Sampler: independent|stratified|lhs|sobol; stratified and lhs need --spp "
                   "[independent]")
        ->type_name("NAME");
    app.add_option("--filter", o.filter,
                   "Pixel filter: box|tent|gaussian|blackman-harris (filter importance sampling; "
                   "lt, bdpt, vcm, mlt filter their splats) [box]")
        ->type_name("NAME");
    app.add_option("--texture-filter", o.texture_filter,
                   "Texture minification: trilinear (mip maps, a ray cone's footprint on camera "
                   "paths) or bilinear (full resolution always; distant textures alias) [trilinear]")
        ->type_name("NAME");
    app.add_option("--filter-radius", o.filter_radius,
                   "Filter radius in pixels [box 0.5, tent 1, gaussian 1.5, blackman-harris 2]")
        ->type_name("PX")
        ->check(CLI::Range(0.05f, 8.0f).description(""))
        ->check(kFinite);
    app.add_option("--direct", o.direct,
                   "Direct light: mis (NEE and BSDF sampling by MIS), light (NEE only), bsdf "
                   "(no NEE) [mis]")
        ->type_name("NAME");
    app.add_option("--mis", o.mis, "MIS heuristic: power|balance [power]")->type_name("NAME");
    app.add_option("--light-samples", o.light_samples, "Shadow rays per vertex [1]")
        ->type_name("N")
        ->check(CLI::Range(1u, 256u).description(""));
    app.add_option("--hemisphere", o.hemisphere,
                   "Next direction: bsdf (importance), cosine, uniform [bsdf]")
        ->type_name("NAME");
    app.add_option("--rr", o.rr,
                   "Russian roulette: throughput (survive with max throughput) or fixed:ALPHA "
                   "(absorb with probability ALPHA) [throughput]")
        ->type_name("MODE");
    app.add_option("--rr-depth", o.rr_depth, "Bounce from which Russian roulette may end paths [3]")
        ->type_name("N");
    app.add_option("--branching", o.branching,
                   "Secondary rays at the first hit; 1 is path tracing [1]")
        ->type_name("K")
        ->check(CLI::Range(1u, 1024u).description(""));
    app.add_option("--ao-radius", o.ao_radius,
                   "Ambient occlusion (--integrator ao) distance [10% of the scene's diagonal]")
        ->type_name("DIST")
        ->check(CLI::NonNegativeNumber.description(""))
        ->check(kFinite);
    app.add_option("--bdpt-strategy", o.bdpt_strategy,
                   "bdpt: render only strategy S,T (S light vertices, T camera vertices), "
                   "MIS-weighted")
        ->type_name("S,T");
    app.add_flag("--bdpt-unweighted", o.bdpt_unweighted,
                 "bdpt: --bdpt-strategy without its MIS weight (the strategy alone)");
    app.add_flag("--bdpt-mosaic", o.bdpt_mosaic,
                 "bdpt: every strategy for paths of 0 to 4 bounces in one image: row = "
                 "bounces, column = S; --spp per cell, --time split over the cells");
    app.add_option("--bdpt-lvc", o.bdpt_lvc,
                   "bdpt, vcm: light vertex caching, M connections per camera vertex to random "
                   "cached light vertices instead of its own light subpath's; 0 is off [0]")
        ->type_name("M")
        ->check(CLI::Range(0u, 64u).description(""));
    app.add_option("--bdpt-memory", o.bdpt_memory_mib,
                   "bdpt, vcm: light vertex buffer per pass in MiB; larger images go in tiles "
                   "[256]")
        ->type_name("MIB")
        ->check(CLI::Range(1u, 1u << 20).description(""));
    app.add_option("--photons", o.photons,
                   "pm: photon paths for the global map [200000]; sppm: photon paths per pass "
                   "[one per pixel]")
        ->type_name("N")
        ->check(CLI::Range(uint64_t(1), uint64_t(0xffffffffu)).description(""));
    app.add_option("--caustic-photons", o.caustic_photons,
                   "pm: photon paths for the caustic map (only L S+ D photons are kept) "
                   "[1000000]")
        ->type_name("N")
        ->check(CLI::Range(uint64_t(0), uint64_t(0xffffffffu)).description(""));
    app.add_option("--final-gather", o.final_gather,
                   "pm: gather rays per sample from the first diffuse hit, which read the "
                   "global map where they land; 0 reads it at the hit itself [8]")
        ->type_name("N")
        ->check(CLI::Range(0u, 255u).description(""));
    app.add_flag("--final-gather-cache", o.final_gather_cache,
                 "pm: read the final gather's diffuse part from an irradiance cache whose "
                 "records gather from the global map (Jensen's photon mapper); the --ic-* "
                 "options apply");
    app.add_option("--knn", o.knn, "pm: photons per radiance estimate (k nearest) [50]")
        ->type_name("K")
        ->check(CLI::Range(1u, 256u).description(""));
    app.add_option("--pm-max-radius", o.pm_max_radius,
                   "pm: largest search radius of an estimate [2% of the scene's diagonal]")
        ->type_name("DIST")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--pm-filter", o.pm_filter,
                   "pm: density estimation kernel: cone|epanechnikov|box [cone]")
        ->type_name("NAME");
    app.add_option("--sppm-radius", o.sppm_radius,
                   "sppm: initial search radius [2 pixel footprints at the scene's centre]")
        ->type_name("DIST")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--sppm-alpha", o.sppm_alpha,
                   "sppm: fraction of each pass's photons kept as the radius shrinks [0.667]")
        ->type_name("A")
        ->check(CLI::Range(0.01f, 1.0f).description(""))
        ->check(kFinite);
    app.add_option("--mlt-mode", o.mlt_mode,
                   "mlt: mmlt (multiplexed, over bdpt's strategies, a chain per path length) or "
                   "pssmlt (Kelemen's primary sample space over pt) [mmlt]")
        ->type_name("MODE");
    app.add_option("--mlt-target", o.mlt_target,
                   "mlt: what the chains' density follows: tile (luminance times (image mean / "
                   "its 8x8 tile's mean)^0.65, both from the bootstrap, so dim regions get their "
                   "share) or luminance [tile]")
        ->type_name("T");
    app.add_option("--mlt-large-step", o.mlt_large_step,
                   "mlt: probability that a mutation is a large step (a fresh path) [0.3]")
        ->type_name("P")
        ->check(CLI::Range(0.0f, 1.0f).description(""))
        ->check(kFinite);
    app.add_option("--mlt-sigma", o.mlt_sigma,
                   "mlt: standard deviation of a small step in primary sample space (mmlt: the "
                   "light subpath's coordinates a quarter of it) [0.01]")
        ->type_name("S")
        ->check(CLI::Range(1e-7f, 1.0f).description(""))
        ->check(kFinite);
    app.add_option("--mlt-bootstrap", o.mlt_bootstrap,
                   "mlt: independent paths (mmlt: per path length) that estimate the image's "
                   "brightness and choose the chains' start states [100000]")
        ->type_name("N")
        ->check(CLI::Range(1u, 1u << 26).description(""));
    app.add_option("--mlt-direct", o.mlt_direct,
                   "mlt: the direct light (bounces 0 and 1) rendered apart by path tracing, "
                   "R samples per pixel for every mutation per pixel, the chains sampling the "
                   "rest; 0: the chains sample it too; auto: R is the direct light's share of the "
                   "image's brightness, from the bootstrap (pssmlt: from the first direct "
                   "samples) [auto]")
        ->type_name("R");
    app.add_option("--mlt-chains", o.mlt_chains,
                   "mlt: Markov chains run in parallel on each device; --spp counts mutations per pixel "
                   "[one per pixel, at most 65536 on a GPU and 1024 per compute unit on a CPU]")
        ->type_name("N")
        ->check(CLI::Range(1u, 1u << 24).description(""));
    app.add_option("--ic-error", o.ic_error,
                   "ic: Ward's accuracy a: a record serves points where its error "
                   "|x - xi| / Ri + sqrt(1 - n.ni) is below a; smaller is more records [0.2]")
        ->type_name("A")
        ->check(kFinite);
    app.add_option("--ic-rays", o.ic_rays,
                   "ic: stratified hemisphere rays per record [256]")
        ->type_name("N");
    app.add_option("--ic-min-spacing", o.ic_min_spacing,
                   "ic: smallest validity radius a Ri of a record, in pixel footprints [1.5]")
        ->type_name("PIXELS")
        ->check(kFinite);
    app.add_option("--ic-max-spacing", o.ic_max_spacing,
                   "ic: largest validity radius a Ri of a record, in pixel footprints [32]")
        ->type_name("PIXELS")
        ->check(kFinite);
    app.add_flag("--ic-no-gradients", o.ic_no_gradients,
                 "ic: interpolate records without Ward and Heckbert's irradiance gradients");
    app.add_flag("--ic-show-records", o.ic_show_records,
                 "ic: paint the pixels whose camera ray placed a record red");
    app.add_option("--ic-photons", o.ic_photons,
                   "ic: records read a global photon map of N paths where their rays land "
                   "(--knn, --pm-max-radius, --pm-filter apply) instead of path tracing on [0]")
        ->type_name("N")
        ->check(CLI::Range(uint64_t(0), uint64_t(0xffffffffu)).description(""));
    app.add_option("--indirect", o.indirect,
                   "indirect1: how a path x <- y <- light is found: receiver (BSDF ray from x, "
                   "light sample at y), source (ray from a light to y, y connected to x) or "
                   "surface (y uniform over the surfaces, connected to x and a light) [receiver]")
        ->type_name("NAME");
    app.add_option("--vcm-mode", o.vcm_mode,
                   "vcm: the techniques of the one estimator: vcm (connections and merging), "
                   "bpt (connections: bdpt), ppm (merging: photon mapping), lt or pt [vcm]")
        ->type_name("MODE");
    app.add_option("--vcm-radius", o.vcm_radius,
                   "vcm: the first pass's merge radius [pixel footprints at the scene's centre: 2 "
                   "with --vcm-shrink pixel, as sppm's, 1 with pass]")
        ->type_name("DIST")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--vcm-shrink", o.vcm_shrink,
                   "vcm: how the merge radius shrinks: pixel (each pixel's own, shrunk as sppm's by "
                   "the merges its first merging vertex finds: a pixel that finds none keeps its "
                   "radius; needs the box filter) or pass (one radius for every pixel, by "
                   "--vcm-alpha's rate) [pixel; pass with another filter]")
        ->type_name("RULE");
    app.add_option("--vcm-merge", o.vcm_merge,
                   "vcm: where a camera path merges: first (at its first vertex with a non-delta "
                   "lobe, where photon mapping gathers; the MIS weights count that merge alone) or "
                   "all (at every such vertex, as Georgiev et al. 2012) [first]")
        ->type_name("WHERE");
    app.add_option("--vcm-light-paths", o.vcm_light_paths_text,
                   "vcm: light subpaths per pixel and pass, 1 to 64 or auto: a camera path "
                   "connects to one and merges with all, so more of them make merging denser for "
                   "their cost (caustics seen through glass, at the cost of a light subpath each), "
                   "and light tracing takes them all; auto renders 16 passes with 1, then 3 each "
                   "with 1, 2 and 4, and keeps the one whose passes gave the least relMSE x "
                   "seconds (1 when split over devices or ranks, or with --spp below 50) [auto]")
        ->type_name("K")
        ->check(CLI::IsMember({"auto"}) | CLI::Range(1u, 64u));
    app.add_flag("--vcm-merged", o.vcm_merged,
                 "vcm: add a 'merged' layer to the EXR: the part of each pixel that merging "
                 "contributed");
    app.add_option("--vcm-alpha", o.vcm_alpha,
                   "vcm: with --vcm-shrink pixel the fraction of a pixel's merges kept as its radius "
                   "shrinks, as sppm's; with pass, radius of pass i is r (i + 1)^((alpha - 1) / 2) "
                   "[0.667 with pixel, as sppm's, 0.75 with pass]")
        ->type_name("A")
        ->check(CLI::Range(0.01f, 1.0f).description(""))
        ->check(kFinite);
    stats_opt = app.add_option("--stats", stats_value,
                               "Write render statistics as JSON to FILE, or stdout when no FILE")
                    ->expected(0, 1)
                    ->type_name("[FILE]");
    app.add_flag("--variance", o.variance,
                 "Add a 'variance' layer to the EXR: the variance of each pixel's estimate");
    app.add_option("--aov", o.aovs,
                   "First-hit layers for the EXR: albedo,normal,depth,position,material-id,variance "
                   "(averaged over each pixel's first 64 samples)")
        ->type_name("LIST")
        ->delimiter(',');
    app.add_flag("--aov-pfm", o.aov_pfm,
                 "Also write OUTPUT.color.pfm, .albedo.pfm and .normal.pfm for Intel Open Image "
                 "Denoise (oidnDenoise --hdr, --alb, --nrm)");
    app.add_option("--reference", o.reference,
                   "Print relMSE against this image as the render goes, and put it in --stats")
        ->type_name("FILE");
    app.add_option("--checkpoint", o.checkpoint,
                   "Save the render's state to FILE every --checkpoint-interval seconds and at "
                   "the end (also when interrupted)")
        ->type_name("FILE");
    app.add_option("--checkpoint-interval", o.checkpoint_interval,
                   "Seconds between checkpoints [60]")
        ->type_name("SECONDS")
        ->check(CLI::PositiveNumber.description(""))
        ->check(kFinite);
    app.add_option("--resume", o.resume,
                   "Continue the render saved in FILE; --spp stays the total sample count")
        ->type_name("FILE");
    app.add_option("--limit", o.limits,
                   "Change a loader limit, e.g. triangles=1G or memory=64G (repeatable; "
                   "names in the README)")
        ->type_name("NAME=VALUE")
        ->allow_extra_args(false);
    app.add_flag("--lenient", o.lenient,
                 "Warn about images that cannot be decoded (magenta instead) and texCoord "
                 "sets other than 0 or 1 (0 instead), rather than failing");
    app.add_flag("-q,--quiet", o.quiet, "Print errors only");
    app.add_flag("-v,--verbose", o.verbose, "Print details: device, kernel builds, BVH");
    app.add_option("--kernel-dir", o.kernel_dir,
                   "Load kernel sources from this folder instead of the built-in ones")
        ->type_name("DIR");
    app.add_option("--dump-kernels", o.dump_kernels,
                   "Write each kernel program's source, as a device is given it, and its build "
                   "options (programs.tsv) to a new folder, and exit")
        ->type_name("DIR");
  }
};

bool parse_resolution(const std::string& s, uint32_t* w, uint32_t* h) {
  const size_t x = s.find_first_of("xX");
  if (x == std::string::npos || x == 0 || x + 1 >= s.size()) return false;
  const std::string a = s.substr(0, x), b = s.substr(x + 1);
  if (a.find_first_not_of("0123456789") != std::string::npos ||
      b.find_first_not_of("0123456789") != std::string::npos || a.size() > 5 || b.size() > 5)
    return false;
  *w = static_cast<uint32_t>(std::stoul(a));
  *h = static_cast<uint32_t>(std::stoul(b));
  return *w >= 1 && *h >= 1 && *w <= kMaxFilmSide && *h <= kMaxFilmSide;
}

}  // namespace

float filter_default_radius(const std::string& filter) {
  return filter == "box" ? 0.5f : filter == "tent" ? 1.0f : filter == "gaussian" ? 1.5f
       : filter == "blackman-harris" ? 2.0f : 0.0f;
}

bool parse_strategy(const std::string& text, uint32_t* s, uint32_t* t) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos || comma == 0 || comma + 1 >= text.size()) return false;
  const std::string a = text.substr(0, comma), b = text.substr(comma + 1);
  if (a.find_first_not_of("0123456789") != std::string::npos ||
      b.find_first_not_of("0123456789") != std::string::npos || a.size() > 4 || b.size() > 4)
    return false;
  *s = static_cast<uint32_t>(std::stoul(a));
  *t = static_cast<uint32_t>(std::stoul(b));
  // s = 1, t = 1 (a light point seen by the camera) is not one of bdpt's strategies.
  return *t >= 1 && *s + *t >= 2 && !(*s == 1 && *t == 1);
}

std::string usage_text() {
  Parser p;
  return p.app.help();
}

std::optional<Options> parse_options(int argc, const char* const* argv, std::ostream& out) {
  Parser p;
  try {
    p.app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << p.app.help();
    return std::nullopt;
  } catch (const CLI::CallForVersion&) {
    out << p.app.version() << "\n";
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    throw Error(ExitCode::Usage, std::string(e.what()) + "\nRun 'clpt --help' for the options.");
  }
  Options o = p.o;
  if (o.list_devices || !o.dump_kernels.empty()) return o;
  if (o.scene.empty())
    throw Error(ExitCode::Usage, "no scene given\nusage: clpt [options] scene.gltf|scene.glb "
                                 "(run 'clpt --help' for the options)");
  if (!p.resolution.empty() && !parse_resolution(p.resolution, &o.width, &o.height))
    throw Error(ExitCode::Usage, "--resolution " + p.resolution +
                                     ": expected WxH with each side from 1 to 16384, e.g. 640x480");
  if (!p.background.empty()) {
    // R,G,B: three finite numbers >= 0.
    std::string rest = p.background;
    bool ok = true;
    for (int i = 0; i < 3 && ok; ++i) {
      const size_t comma = rest.find(',');
      if ((i < 2) != (comma != std::string::npos)) {
        ok = false;
        break;
      }
      const std::string item = rest.substr(0, comma);
      try {
        size_t used = 0;
        o.background[i] = std::stof(item, &used);
        ok = used == item.size() && std::isfinite(o.background[i]) && o.background[i] >= 0.0f;
      } catch (const std::exception&) {
        ok = false;
      }
      rest = comma == std::string::npos ? std::string() : rest.substr(comma + 1);
    }
    if (!ok)
      throw Error(ExitCode::Usage, "--background " + p.background +
                                       ": expected R,G,B, three finite numbers >= 0, e.g. 1,1,1");
    if (!o.env.empty())
      throw Error(ExitCode::Usage, "--background and --env exclude each other");
  }
  {
    LoadLimits limits;  // names and values are checked here, before any work
    for (const std::string& spec : o.limits) limits.set(spec);
  }
  if (!std::isfinite(o.env_rotate))
    throw Error(ExitCode::Usage, "--env-rotate needs a finite number of degrees");
  if (p.time_opt->count() && !p.spp_opt->count()) o.spp = 0;  // --time alone: no sample limit
  if (p.stats_opt->count()) o.stats = p.stats_value.empty() ? std::string("-") : p.stats_value;
  o.caustic_photons_set = p.app.count("--caustic-photons") > 0;
  o.final_gather_set = p.app.count("--final-gather") > 0;
  o.knn_set = p.app.count("--knn") > 0;
  o.pm_filter_set = p.app.count("--pm-filter") > 0;
  o.sppm_alpha_set = p.app.count("--sppm-alpha") > 0;
  for (const char* name : {"--mlt-mode", "--mlt-target", "--mlt-large-step", "--mlt-sigma",
                           "--mlt-bootstrap", "--mlt-direct", "--mlt-chains"})
    o.mlt_set = o.mlt_set || p.app.count(name) > 0;
  for (const char* name : {"--ic-error", "--ic-rays", "--ic-min-spacing", "--ic-max-spacing",
                           "--ic-no-gradients", "--ic-show-records", "--ic-photons"})
    o.ic_set = o.ic_set || p.app.count(name) > 0;
  o.indirect_set = p.app.count("--indirect") > 0;
  o.vcm_shrink_set = p.app.count("--vcm-shrink") > 0;
  o.vcm_alpha_set = p.app.count("--vcm-alpha") > 0;
  for (const char* name :
       {"--vcm-mode", "--vcm-radius", "--vcm-alpha", "--vcm-shrink", "--vcm-merge", "--vcm-light-paths",
        "--vcm-merged"})
    o.vcm_set = o.vcm_set || p.app.count(name) > 0;
  if (o.quiet && o.verbose) throw Error(ExitCode::Usage, "--quiet and --verbose exclude each other");
  auto one_of = [](const char* option, const std::string& value,
                   std::initializer_list<const char*> names) {
    std::string list;
    for (const char* n : names) {
      if (value == n) return;
      list += (list.empty() ? "" : ", ") + std::string(n);
    }
    throw Error(ExitCode::Usage, std::string(option) + " " + value + ": expected one of " + list);
  };
  one_of("--sampler", o.sampler, {"independent", "stratified", "lhs", "sobol"});
  one_of("--filter", o.filter, {"box", "tent", "gaussian", "blackman-harris"});
  one_of("--texture-filter", o.texture_filter, {"trilinear", "bilinear"});
  for (const std::string& a : o.aovs) {
    one_of("--aov", a, {"albedo", "normal", "depth", "position", "material-id", "variance"});
    if (std::count(o.aovs.begin(), o.aovs.end(), a) > 1)
      throw Error(ExitCode::Usage, "--aov " + a + ": named twice");
    if (a == "variance") o.variance = true;
  }
  if (o.filter_radius == 0.0f) o.filter_radius = filter_default_radius(o.filter);
  one_of("--direct", o.direct, {"mis", "light", "bsdf"});
  one_of("--mis", o.mis, {"power", "balance"});
  one_of("--hemisphere", o.hemisphere, {"bsdf", "cosine", "uniform"});
  if (o.rr != "throughput") {
    const std::string prefix = "fixed:";
    bool ok = o.rr.compare(0, prefix.size(), prefix) == 0 && o.rr.size() > prefix.size();
    if (ok) {
      try {
        size_t used = 0;
        const float a = std::stof(o.rr.substr(prefix.size()), &used);
        ok = used == o.rr.size() - prefix.size() && a >= 0.0f && a < 1.0f;
      } catch (const std::exception&) {
        ok = false;
      }
    }
    if (!ok)
      throw Error(ExitCode::Usage, "--rr " + o.rr + ": expected throughput or fixed:ALPHA with "
                                   "0 <= ALPHA < 1");
  }
  const IntegratorInfo& row = integrator_info(o.integrator);  // throws for an unknown name
  if (row.film == FilmKind::Progressive) {
    // Its pixels are progressive estimates with statistics of their own (radius, photon count).
    if (o.variance)
      throw Error(ExitCode::Usage, "--variance is not available with --integrator " + o.integrator +
                                       ": a pixel is one progressive estimate, not a mean of samples");
    if (!o.checkpoint.empty() || !o.resume.empty())
      throw Error(ExitCode::Usage, "--checkpoint and --resume are not supported with "
                                   "--integrator " + o.integrator + " (its pixel statistics are not saved)");
  }
  if (row.film == FilmKind::Splats) {
    // Splatted films: no per-pixel sample variance, and float atomics in no fixed order, so a
    // resumed render could not equal an uninterrupted one bit for bit.
    if (o.variance)
      throw Error(ExitCode::Usage, "--variance is not available with --integrator " + o.integrator +
                                       ": light paths splat into any pixel, so there is no "
                                       "per-pixel sample variance");
    if (!o.checkpoint.empty() || !o.resume.empty())
      throw Error(ExitCode::Usage, "--checkpoint and --resume are not supported with "
                                   "--integrator " + o.integrator + " (its splatted sums are not "
                                   "reproducible bit for bit)");
  }
  const auto reads = [&](unsigned group) { return (row.options & group) != 0u; };
  if (!reads(OPTIONS_PHOTONS) && (o.photons || o.sppm_radius > 0.0f || o.sppm_alpha_set))
    throw Error(ExitCode::Usage, "--photons, --sppm-radius and --sppm-alpha need --integrator pm "
                                 "or sppm");
  // The irradiance cache's options apply to ic and to pm's cached final gather; photon
  // estimates' options to pm and to ic's photon-gathering records.
  const bool ic_cache = reads(OPTIONS_IC) || (reads(OPTIONS_PM) && o.final_gather_cache);
  const bool ic_photon_records = reads(OPTIONS_IC) && o.ic_photons > 0;
  if (!reads(OPTIONS_PM) && (o.caustic_photons_set || o.final_gather_set || o.final_gather_cache))
    throw Error(ExitCode::Usage, "--caustic-photons, --final-gather and --final-gather-cache need "
                                 "--integrator pm");
  if (!reads(OPTIONS_PM) && !ic_photon_records &&
      (o.knn_set || o.pm_max_radius > 0.0f || o.pm_filter_set))
    throw Error(ExitCode::Usage, "--knn, --pm-max-radius and --pm-filter need --integrator pm, "
                                 "or ic with --ic-photons");
  if (o.final_gather_cache && o.final_gather_set && o.final_gather == 0)
    throw Error(ExitCode::Usage, "--final-gather-cache caches the final gather: --final-gather 0 "
                                 "(no final gather) leaves nothing to cache");
  if (!reads(OPTIONS_SPPM) && (o.sppm_radius > 0.0f || o.sppm_alpha_set))
    throw Error(ExitCode::Usage, "--sppm-radius and --sppm-alpha need --integrator sppm");
  if (!reads(OPTIONS_AO) && o.ao_radius > 0.0f)
    throw Error(ExitCode::Usage, "--ao-radius needs --integrator ao");
  if (!reads(OPTIONS_MLT) && o.mlt_set)
    throw Error(ExitCode::Usage, "--mlt-mode, --mlt-target, --mlt-large-step, --mlt-sigma, "
                                 "--mlt-bootstrap, --mlt-direct and --mlt-chains need "
                                 "--integrator mlt");
  if (reads(OPTIONS_MLT)) {
    one_of("--mlt-mode", o.mlt_mode, {"pssmlt", "mmlt"});
    one_of("--mlt-target", o.mlt_target, {"tile", "luminance"});
    if (o.mlt_direct != "auto") {
      char* end = nullptr;
      const float r = std::strtof(o.mlt_direct.c_str(), &end);
      if (o.mlt_direct.empty() || *end != '\0' || !(r >= 0.0f) || !std::isfinite(r) || r > 64.0f)
        throw Error(ExitCode::Usage, "--mlt-direct must be auto or a number in [0, 64], not '" +
                                         o.mlt_direct + "'");
      o.mlt_direct_ratio = r;
    }
    // A chain's path must be a function of its vector alone: one stream of dimensions.
    if (o.light_samples != 1 || o.branching != 1)
      throw Error(ExitCode::Usage, "--integrator mlt mutates one path of one shadow ray per "
                                   "vertex: --light-samples and --branching must stay 1");
    if (o.sampler != "independent")
      throw Error(ExitCode::Usage, "--integrator mlt takes its random numbers from its chains: "
                                   "--sampler does not apply");
  }
  if (!ic_cache && o.ic_set)
    throw Error(ExitCode::Usage, "--ic-error, --ic-rays, --ic-min-spacing, --ic-max-spacing, "
                                 "--ic-no-gradients, --ic-show-records and --ic-photons need "
                                 "--integrator ic (or pm with --final-gather-cache)");
  if (!reads(OPTIONS_IC) && o.ic_photons)
    throw Error(ExitCode::Usage, "--ic-photons is ic's: pm --final-gather-cache's records read pm's "
                                 "global map (--photons)");
  if (ic_cache) {
    if (!(o.ic_error > 0.0f && o.ic_error <= 1.0f))
      throw Error(ExitCode::Usage, "--ic-error " + std::to_string(o.ic_error) +
                                       ": expected 0 < A <= 1");
    if (o.ic_rays < 1 || o.ic_rays > 16384)
      throw Error(ExitCode::Usage, "--ic-rays " + std::to_string(o.ic_rays) +
                                       ": expected 1 to 16384 rays per record");
    if (!(o.ic_min_spacing > 0.0f) || !std::isfinite(o.ic_max_spacing))
      throw Error(ExitCode::Usage, "--ic-min-spacing and --ic-max-spacing need positive, finite "
                                   "pixel counts");
    if (o.ic_min_spacing > o.ic_max_spacing)
      throw Error(ExitCode::Usage, "--ic-min-spacing " + std::to_string(o.ic_min_spacing) +
                                       " is above --ic-max-spacing " +
                                       std::to_string(o.ic_max_spacing));
    // Under --time the records refine for as many rounds as a quarter of the time allows,
    // so a resumed render's cache would not be the interrupted one's.
    if (o.time_limit > 0.0 && (!o.checkpoint.empty() || !o.resume.empty()))
      throw Error(ExitCode::Usage, "--integrator " + o.integrator + " with --time refines its "
                                   "irradiance cache for a share "
                                   "of the time, which a resumed render cannot repeat: use "
                                   "--spp with --checkpoint and --resume");
    // The cache holds what a diffuse surface's BSDF samples find; the image's estimator
    // choices are pt's, but the walk samples the BSDF itself.
    if (reads(OPTIONS_IC) && (o.hemisphere != "bsdf" || o.branching != 1))
      throw Error(ExitCode::Usage, "--integrator ic samples the BSDF at every vertex: "
                                   "--hemisphere must stay bsdf and --branching 1");
  }
  if (!reads(OPTIONS_INDIRECT) && o.indirect_set)
    throw Error(ExitCode::Usage, "--indirect needs --integrator indirect1");
  if (reads(OPTIONS_INDIRECT)) one_of("--indirect", o.indirect, {"receiver", "source", "surface"});
  if (!reads(OPTIONS_VCM) && o.vcm_set)
    throw Error(ExitCode::Usage, "--vcm-mode, --vcm-radius, --vcm-alpha, --vcm-shrink, --vcm-merge, "
                                 "--vcm-light-paths and --vcm-merged need --integrator vcm");
  if (reads(OPTIONS_VCM)) {
    one_of("--vcm-mode", o.vcm_mode, {"vcm", "bpt", "ppm", "lt", "pt"});
    // A light vertex connected to the camera is weighted with the eta of the one pixel its
    // film position lies in: a wider filter would spread it over pixels of other radii.
    const bool pixel_box = o.filter == "box" && o.filter_radius == 0.5f;
    if (o.vcm_shrink.empty()) o.vcm_shrink = pixel_box ? "pixel" : "pass";
    one_of("--vcm-shrink", o.vcm_shrink, {"pass", "pixel"});
    one_of("--vcm-merge", o.vcm_merge, {"all", "first"});
    if (o.vcm_shrink == "pixel" && !pixel_box)
      throw Error(ExitCode::Usage, "--vcm-shrink pixel needs the box filter of radius 0.5");
    // The equal-time sweeps of docs/BENCHMARKS.md (session 32) chose both defaults.
    if (o.vcm_alpha == 0.0f) o.vcm_alpha = o.vcm_shrink == "pixel" ? kVcmPixelAlpha : kVcmPassAlpha;
    // CLI11 checked it: auto or a whole number from 1 to 64.
    o.vcm_light_paths =
        o.vcm_light_paths_text == "auto" ? 0u : static_cast<uint32_t>(std::stoul(o.vcm_light_paths_text));
  }
  if (o.pm_filter != "cone" && o.pm_filter != "epanechnikov" && o.pm_filter != "box")
    throw Error(ExitCode::Usage, "--pm-filter " + o.pm_filter + ": expected cone, epanechnikov "
                                 "or box");
  if ((!o.bdpt_strategy.empty() || o.bdpt_unweighted || o.bdpt_mosaic) && !reads(OPTIONS_BDPT))
    throw Error(ExitCode::Usage, "--bdpt-strategy, --bdpt-unweighted and --bdpt-mosaic need "
                                 "--integrator bdpt");
  if (o.bdpt_lvc && !reads(OPTIONS_LVC))
    throw Error(ExitCode::Usage, "--bdpt-lvc needs --integrator bdpt or vcm");
  if (o.bdpt_unweighted && o.bdpt_strategy.empty() && !o.bdpt_mosaic)
    throw Error(ExitCode::Usage, "--bdpt-unweighted needs --bdpt-strategy S,T or --bdpt-mosaic");
  if (o.bdpt_mosaic && !o.bdpt_strategy.empty())
    throw Error(ExitCode::Usage, "--bdpt-mosaic renders every strategy: leave out --bdpt-strategy");
  if (o.bdpt_mosaic && (o.reference.size() || o.stats || o.save_every > 0.0 || !o.aovs.empty() || o.aov_pfm))
    throw Error(ExitCode::Usage, "--bdpt-mosaic writes a mosaic image: --reference, --stats, "
                                 "--save-every, --aov and --aov-pfm do not apply");
  if (!o.bdpt_strategy.empty()) {
    uint32_t s = 0, t = 0;
    if (!parse_strategy(o.bdpt_strategy, &s, &t))
      throw Error(ExitCode::Usage, "--bdpt-strategy " + o.bdpt_strategy +
                                       ": expected S,T with S >= 0 light vertices and T >= 1 "
                                       "camera vertices, S + T >= 2, not 1,1");
    if (s + t - 2 > o.max_depth)
      throw Error(ExitCode::Usage, "--bdpt-strategy " + o.bdpt_strategy + " has " +
                                       std::to_string(s + t - 2) + " bounces, more than "
                                       "--max-depth " + std::to_string(o.max_depth));
  }
  return o;
}

}  // namespace clpt
