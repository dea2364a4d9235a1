// Turns a Scene into an image: BVH build, upload, integrator passes, film resolve.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cl/context.h"
#include "integrators/integrator.h"
#include "io/image_io.h"
#include "render/checkpoint.h"
#include "render/cluster.h"
#include "render/aov.h"
#include "render/film.h"
#include "render/light_table.h"
#include "render/scene_buffers.h"
#include "scene/scene.h"

namespace clpt {

struct RenderSettings {
  uint32_t width = 0, height = 0;  // 0: from the camera (render/camera_setup.h)
  uint64_t spp = 64;               // samples per pixel; 0 = no limit (a time limit must be set)
  double time_limit = 0.0;         // seconds; 0 = none. With spp, whichever ends first.
  uint32_t max_depth = 8;
  uint32_t rr_depth = 3;
  uint32_t seed = 0;
  std::string integrator = "pt";
  // Estimator choices (see kernels/shared/render_types.h for the enums).
  uint32_t sampler = 0;        // dev::SamplerType
  uint32_t filter = 0;         // dev::PixelFilter of camera samples
  float filter_radius = 0.5f;  // pixels
  bool mipmaps = true;         // textures with mip chains, read with ray cones (--texture-filter)
  uint32_t aovs = 0;           // AovBits (render/aov.h): first-hit AOVs to render beside the image
  uint32_t direct = 0;         // dev::DirectStrategy
  uint32_t mis = 0;            // dev::MisHeuristic
  uint32_t light_samples = 1;  // shadow rays per vertex
  uint32_t hemisphere = 0;     // dev::HemisphereSampling
  uint32_t rr = 0;             // dev::RussianRoulette
  float rr_absorb = 0.5f;      // absorption probability with RR_FIXED
  uint32_t branching = 1;      // continuations from the first hit
  // Each integrator's own settings (integrators/integrator.h); their defaults are resolved by
  // the integrators, from the scene's diagonal and a pixel's footprint.
  BdptConfig bdpt;                  // bdpt: --bdpt-strategy, --bdpt-unweighted; bdpt and vcm:
                                    //   --bdpt-lvc, --bdpt-memory
  PmConfig pm;                      // pm: maps, final gather, k-NN estimates (ic's too)
  SppmConfig sppm;                  // sppm: photons per pass, radius, alpha
  AoConfig ao;                      // ao: radius
  MltConfig mlt;                    // mlt: chains, bootstrap, step sizes
  IcConfig ic;                      // ic: accuracy, rays, spacing
  VcmConfig vcm;                    // vcm: mode, radius (0: a pixel footprint at the centre), alpha
  uint32_t indirect = 0;            // indirect1: dev::IndirectGenerator
  std::string camera;              // index or name; empty: the first camera or a default one
  std::string env_file;            // equirectangular environment map; empty: none
  ImageLimits env_limits;          // the largest map read (--limit image-dimension, image-pixels)
  // env_file already read by the caller (the CLI reads it before the device is set up, so a bad
  // map fails fast and cheaply), shared by the renderers made from these settings (its
  // background field is the caller's to set). Null: read env_file here.
  std::shared_ptr<const Environment> environment;
  float env_scale = 1.0f;          // multiplies the map
  float env_rotation = 0.0f;       // degrees about +y
  glm::vec3 background{0.0f};      // constant radiance of escaping rays when there is no map
  float aperture = 0.0f;           // thin-lens aperture radius; 0: pinhole
  float focus_distance = 0.0f;     // 0: distance to the scene's centre along the view
  double target_pass_seconds = 0.0;  // pass length aimed at; 0: 0.03 s on GPUs, 0.1 s otherwise
  uint32_t max_samples_per_pass = 0; // 0: no cap (tests use 1 to force many passes)
};

// One device's part of a render (several with --device A,B or --device all).
struct DeviceShare {
  std::string name;           // the device's name
  std::string label;          // "P:D name (platform)"
  uint64_t samples = 0;       // samples per pixel it rendered
  uint64_t passes = 0;        // passes it ran
  double busy_seconds = 0.0;  // its passes' time, first launch to finish
};

struct RenderStats {
  double bvh_build_seconds = 0.0;
  double kernel_seconds = 0.0;      // program from cache or build, plus the first (compiling) launch
  bool kernel_from_cache = false;
  double render_seconds = 0.0;
  double film_gather_seconds = 0.0;  // the final film: read back, devices' (and ranks') added
  uint64_t passes = 0;
  int bvh_max_leaf = 0;  // triangles per leaf at most (kMaxLeafLanes or kMaxLeafOneAtATime)
  int bvh_depth = 0;
  size_t bvh_nodes = 0;
  int bvh_wide_depth = 0;     // the 4-wide tree the kernels traverse (collapse_bvh4)
  size_t bvh_wide_nodes = 0;
  size_t triangles = 0;
  uint32_t emitters = 0;         // emissive triangles
  uint32_t lights = 0;           // all lights: emissive triangles, punctual, environment
  size_t texture_device_bytes = 0;  // textures with their mip levels
  size_t texture_mip_bytes = 0;     // of those, the mip levels'
  size_t scene_device_bytes = 0;
  size_t film_device_bytes = 0;
  uint64_t connections = 0;      // bdpt: shadow rays of connection strategies
  PhotonStats photons;           // pm, sppm
  MetropolisStats metropolis;    // mlt
  IcStats ic;                    // ic
  VcmStats vcm;                  // vcm
  std::vector<DeviceShare> devices;  // every device, in --device order
};

struct RenderOutput {
  FilmResult film;
  RenderStats stats;
  bool interrupted = false;  // stopped by the stop flag before the target was reached
  std::vector<NamedChannel> layers;  // the integrator's extra images (Integrator::layers)
  std::vector<NamedChannel> aovs;    // RenderSettings::aovs' layers (AovPass::layers)
};

// With several devices, each gets its own copy of the scene, integrator and film, and each pass
// gives every device a disjoint range of sample indices sized by its measured speed (a round:
// all aim at the same pass length, so a slow device holds up a fast one by little); the films
// are added on the host in device order. Every sample is a function of its index, so the image
// equals one device's up to the rounding of the final sum. mlt's devices run chains of their
// own instead, and sppm, whose passes depend on each other, renders on one device only
// (IntegratorInfo::split).
class Renderer {
 public:
  // Builds the BVH, uploads the scene and gets the integrator's kernels ready, on one device
  // or on each of several (non-null, distinct).
  Renderer(const cl::Context& ctx, const Scene& scene, const RenderSettings& settings);
  // cluster: the processes (MPI ranks) that share the render, each with its own devices and
  // a renderer made from the same scene and settings; null: this process alone. With several
  // processes, render(), film_sums(), snapshot(), film_state() and restore() are collective:
  // every rank calls them in the same order, and rank 0 gets the whole film.
  Renderer(const std::vector<const cl::Context*>& contexts, const Scene& scene,
           const RenderSettings& settings, const Cluster* cluster = nullptr);
  ~Renderer();

  // progress(samples done, samples target (0 = none), seconds elapsed, last): called after
  // each pass; `last` says the sample target or the time limit ends the render with this pass
  // (an interrupt may still end it sooner, after any pass).
  using Progress = std::function<void(uint64_t, uint64_t, double, bool)>;
  // Renders until the sample target or the time limit is reached, or *stop becomes true
  // (checked between passes; the pass in flight completes).
  RenderOutput render(const std::atomic<bool>* stop = nullptr, const Progress& progress = {});

  // The raw film (for checkpoints) and its restoration: render() then continues from the
  // restored sample count, so a resumed render equals an uninterrupted one bit for bit.
  FilmState film_state(uint64_t samples_per_pixel) const;
  void restore(const FilmState& state);

  // The film as it stands after `samples_per_pixel` samples (for progress reports).
  FilmResult snapshot(uint64_t samples_per_pixel) const {
    return resolve_film(film_sums(), samples_per_pixel);
  }
  // Every device's film read back and added, in device order (and rank order: on rank 0).
  FilmSums film_sums() const;

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  const std::string& device_name() const { return lanes_device(0).name; }
  size_t device_count() const { return lanes_.size(); }

 private:
  struct Lane;  // one device's context, scene, integrator, film and AOVs (renderer.cpp)
  const cl::DeviceInfo& lanes_device(size_t i) const;
  // The devices of every rank: their shares, connections and vcm figures, on rank 0
  // (collective).
  void gather_device_stats();
  // The integrator's extra layers (vcm's merged part) and the AOVs, of every device and rank
  // added, on rank 0 (collective).
  std::vector<NamedChannel> gathered_layers(uint64_t done) const;
  std::vector<NamedChannel> gathered_aovs() const;
  // Runs f(i) for every lane i that busy(i) names, each on a host thread of its own (the
  // first on this one), waits for all, and rethrows the first lane's error.
  void for_each_lane(const std::function<bool(size_t)>& busy, const std::function<void(size_t)>& f);
  // Runs every lane's range of the round ([first, first + n) each; n = 0: idle) and waits.
  void run_round(const std::vector<uint64_t>& first, const std::vector<uint64_t>& n);
  // The integrator's start-up work (Integrator::setup_items) shared out over all `all`
  // devices of every rank, this rank's from index `mine` on (collective).
  void share_setup(size_t all, size_t mine);

  Cluster alone_;
  const Cluster* cluster_ = &alone_;
  RenderSettings settings_;
  uint32_t width_ = 0, height_ = 0;
  dev::RenderParams params_{};
  RenderStats stats_;
  std::vector<std::unique_ptr<Lane>> lanes_;
  uint64_t start_spp_ = 0;  // samples already in the film (restored from a checkpoint)
  bool setup_shared_ = false;  // share_setup has run
};

}  // namespace clpt
