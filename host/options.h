// The command line: one struct of options and one usage text (clpt --help).
#pragma once

#include <cstdint>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace clpt {

struct Options {
  std::string scene;              // .gltf or .glb
  std::string output = "clpt.exr";
  std::string view = "standard";  // io/view_transform.h: how 8-bit output shows radiance
  float exposure = 0.0f;          // stops, before the view transform
  double save_every = 0.0;        // > 0: write the output this often while rendering
  std::string device;             // --device spec; empty: first GPU, else PoCL
  bool list_devices = false;
  std::string dump_kernels;       // --dump-kernels DIR: write the programs' sources and exit
  uint64_t spp = 64;              // 0: no sample limit (only with --time)
  double time_limit = 0.0;        // seconds; 0: none
  double pass_seconds = 0.0;      // pass length aimed at; 0: the renderer's default
  uint32_t width = 0, height = 0; // 0: from the camera's aspect ratio
  std::string camera;
  std::string env;                // equirectangular environment map (.hdr, .exr); empty: none
  float env_scale = 1.0f;
  float env_rotate = 0.0f;        // degrees about +y
  float background[3] = {0.0f, 0.0f, 0.0f};  // radiance of escaping rays without --env
  float aperture = 0.0f;          // thin-lens aperture radius; 0: pinhole
  float focus_distance = 0.0f;    // 0: the distance to the scene's centre along the view
  uint32_t max_depth = 8;
  uint32_t seed = 0;
  std::string integrator = "pt";
  // Estimator choices, as names; parse_options validates them.
  std::string sampler = "independent";
  std::string filter = "box";     // pixel reconstruction filter (camera/pixel_filter.cl)
  float filter_radius = 0.0f;     // pixels; 0: the filter's default (filter_default_radius)
  std::string texture_filter = "trilinear";  // trilinear (mip maps, ray cones) | bilinear
  std::string direct = "mis";
  std::string mis = "power";
  uint32_t light_samples = 1;
  std::string hemisphere = "bsdf";
  std::string rr = "throughput";  // or fixed:ALPHA
  uint32_t rr_depth = 3;
  uint32_t branching = 1;
  float ao_radius = 0.0f;  // 0: 10 % of the scene's bounding-box diagonal
  std::string bdpt_strategy;      // "S,T": render only that BDPT strategy; empty: all
  bool bdpt_unweighted = false;   // that strategy without its MIS weight
  bool bdpt_mosaic = false;       // every strategy of 0..4 bounces in one image
  uint32_t bdpt_memory_mib = 256; // light vertex buffer budget per pass
  uint32_t bdpt_lvc = 0;          // light vertex caching: connections per camera vertex
  // Photon mapping (pm, sppm). The *_set flags record that an option was given.
  uint64_t photons = 0;            // 0: the integrator's default
  uint64_t caustic_photons = 1000000;
  uint32_t final_gather = 8;
  bool final_gather_cache = false;  // pm: the final gather's diffuse part from an irradiance cache
  uint32_t knn = 50;
  float pm_max_radius = 0.0f;      // 0: 2 % of the scene's bounding-box diagonal
  std::string pm_filter = "cone";
  float sppm_radius = 0.0f;        // 0: two pixel footprints at the scene's centre
  float sppm_alpha = 2.0f / 3.0f;
  bool caustic_photons_set = false, final_gather_set = false, knn_set = false,
       pm_filter_set = false, sppm_alpha_set = false;
  // Metropolis (mlt). mlt_set: one of the --mlt-* options was given.
  std::string mlt_mode = "mmlt";
  std::string mlt_target = "tile";
  float mlt_large_step = 0.3f;
  float mlt_sigma = 0.01f;
  uint32_t mlt_bootstrap = 100000;
  std::string mlt_direct = "auto";  // a number >= 0, or auto (MltConfig::direct), as given
  std::optional<float> mlt_direct_ratio;  // --mlt-direct parsed by parse_options; empty: auto
  uint32_t mlt_chains = 0;  // 0: Metropolis::default_chains (one per pixel, capped per device)
  bool mlt_set = false;
  // Irradiance cache (ic). ic_set: one of the --ic-* options was given.
  float ic_error = 0.2f;
  uint32_t ic_rays = 256;
  float ic_min_spacing = 1.5f;
  float ic_max_spacing = 32.0f;
  bool ic_no_gradients = false;
  bool ic_show_records = false;
  uint64_t ic_photons = 0;  // records gather from a global map of this many paths; 0: path traced
  bool ic_set = false;
  // One-bounce indirect light (indirect1): --indirect, the generator of its paths.
  std::string indirect = "receiver";
  bool indirect_set = false;
  // Vertex connection and merging (vcm). vcm_set: one of the --vcm-* options was given.
  std::string vcm_mode = "vcm";
  float vcm_radius = 0.0f;         // 0: one pixel footprint at the scene's centre
  float vcm_alpha = 0.0f;          // 0: the shrink rule's (2/3 per pixel, 0.75 per pass)
  // pass: one radius per pass; pixel: a radius per pixel; empty: pixel with the box filter of
  // radius 0.5, else pass.
  std::string vcm_shrink;
  bool vcm_shrink_set = false, vcm_alpha_set = false;
  bool vcm_merged = false;         // EXR layer "merged": what merging contributed
  std::string vcm_merge = "first"; // where merges are made: first (the first non-delta camera
                                   // vertex), all (every one)
  std::string vcm_light_paths_text = "auto";  // --vcm-light-paths as given: auto or K
  uint32_t vcm_light_paths = 0;    // light subpaths per pixel and pass; 0: auto (parse_options)
  bool vcm_set = false;
  std::optional<std::string> stats;  // "-" for stdout, else a JSON file
  bool variance = false;          // add a variance layer to the EXR
  std::vector<std::string> aovs;  // --aov: albedo, normal, depth, position, material-id, variance
  bool aov_pfm = false;           // --aov-pfm: colour, albedo and normal as PFM for oidnDenoise
  std::string reference;          // image to compare with (relMSE), empty: none
  std::string checkpoint;         // film state written every checkpoint_interval s and at the end
  double checkpoint_interval = 60.0;
  std::string resume;             // continue from this checkpoint
  bool quiet = false, verbose = false;
  std::string kernel_dir;         // load kernel sources from disk (development)
  bool lenient = false;           // undecodable image / bad texCoord: warn and go on
  std::vector<std::string> limits;  // --limit NAME=VALUE (scene/load_limits.h)
};

// Parses argv. Returns nullopt when the program should exit 0 after printing (--help,
// --version) to `out`; throws Error(ExitCode::Usage) with a message for a bad command line.
std::optional<Options> parse_options(int argc, const char* const* argv, std::ostream& out = std::cout);

// The radius --filter NAME has without --filter-radius: box 0.5 (one pixel), tent 1,
// gaussian 1.5 (sigma 0.5, pbrt-v4's default), blackman-harris 2; 0 for an unknown name.
float filter_default_radius(const std::string& filter);

// "S,T" of --bdpt-strategy; false unless a strategy bdpt has.
bool parse_strategy(const std::string& text, uint32_t* s, uint32_t* t);

// The --help text.
std::string usage_text();

}  // namespace clpt
