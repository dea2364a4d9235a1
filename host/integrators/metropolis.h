// Metropolis light transport (--integrator mlt): multiplexed MLT over bdpt's strategies
// (Hachisuka et al. 2014, --mlt-mode mmlt) or primary-sample-space MLT over the path tracer
// (Kelemen et al. 2002, pssmlt). kernels/integrators/mlt.cl, docs/concepts/metropolis.md.
//
// Before the first pass (the renderer's setup, shared out over every device of every rank, or
// else the first pass itself), a bootstrap: `bootstrap` independent paths (fresh primary sample vectors) per
// path length (mmlt: bounces 0 to max_depth; pssmlt: one, all lengths in one path) give
// their target values I; their mean is each length's normalisation b_d. I is the path's
// luminance, or with the tile target (--mlt-target tile, the default) its luminance times
// the pixel's weight from the bootstrap's estimate of the image (tile_importance), which
// sends the chains to dim tiles nearly as often as to bright ones (the weight is fixed before
// the chains start, so any positive weight keeps the estimate unbiased).
// The chains are shared out over the lengths in proportion to b_d (allocate), and each
// chain's start state is drawn from its length's paths in proportion to I (systematic
// resampling), so the chains start in their stationary distribution and there is no start-up
// bias. Then each pass runs every chain for ceil(spp * pixels / chains) proposals: --spp
// counts mutations per pixel. The large steps' proposals are fresh uniform vectors, samples of
// b_d as the bootstrap's paths are, and each chain keeps them as a pool: when a length's pool
// has grown kRestartGrowth times the pool (or bootstrap) its chains started from, its chains
// restart from it, b_d its mean and the starts drawn from it in proportion to I (a 60 s
// render proposes some 40 times the bootstrap's paths), so that b's error, a scale error of
// the whole image, fades as the render runs. Like lt and bdpt its film has splats: no
// per-pixel variance, sums not bit-reproducible unless PoCL runs on one thread.
//
// Both modes render the direct light apart by default (--mlt-direct; as Mitsuba 0.6's MLT
// integrators do with their directSamples, 16 per pixel by default there: Metropolis gains
// nothing on light a path tracer finds at once, and its correlated chains lose). After N
// mutations per pixel the device has taken K = max(1, round(R N)) samples per pixel of pt cut
// at one bounce (pt_render with max_depth 1, the `direct` integrator's kernel, into sums of
// its own, S), and the film's per-pixel sums, which the chains do not use, hold S N / K: the
// film's division by N gives S / K, an unbiased mean whatever K is, at every pass. The chains
// sample bounces 2 on: mmlt's lengths 0 and 1 get no chains, pssmlt's paths leave those
// bounces out (MltParams.first_depth). R is --mlt-direct, or with auto the share of the
// chains' target that bounces 0 and 1 carry: from the bootstrap's lengths for mmlt
// (direct_ratio), from the first direct samples against b for pssmlt, whose bootstrap no
// longer sees them (direct_share); a scene lit mostly directly spends more of its time there
// (docs/concepts/metropolis.md).
#pragma once

#include <cstdint>
#include <memory>

#include "integrators/integrator.h"
#include "integrators/megakernel.h"
#include "shared/mlt_types.h"

namespace clpt {

class Metropolis final : public Integrator {
 public:
  Metropolis(const cl::Context& ctx, const SceneBuffers& scene, const MltConfig& config);
  const char* name() const override { return "mlt"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  // The bootstrap's paths, shared out over the devices (Integrator::setup_items): each
  // device traces its range, and every device then takes b, the tile weights and its chains'
  // starts from all of them.
  uint64_t setup_items(const dev::RenderParams& params) const override;
  std::string setup_part(const dev::RenderParams& params, Film& film, uint64_t first,
                         uint64_t count) override;
  void setup_finish(const dev::RenderParams& params, Film& film, const std::string& parts) override;
  bool pass_invariant() const override { return false; }
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  MetropolisStats metropolis_stats() const override;

  // Chains for an image when --mlt-chains is not given: one per pixel, at most `cap`
  // (default_chain_cap), and no more than fit `budget_bytes` of chain state.
  static uint32_t default_chains(size_t pixels, uint32_t dims, size_t budget_bytes, uint32_t cap);
  // The most chains by default on a device: 65536 on a GPU, which needs tens of thousands of
  // work-items in flight; on a CPU device kCpuChainsPerUnit per compute unit, which is plenty
  // for its threads, and whose fewer, longer chains keep more of their state in the caches.
  static uint32_t default_chain_cap(bool cpu, uint32_t compute_units);
  // Door ajar (128x128, 30 s, two seeds) and the Cornell box (10 s, three seeds), 2 threads,
  // relMSE by --mlt-chains: 16384 (one per pixel) 0.00221 / 0.00142, 4096 0.00200 / 0.00135,
  // 2048 0.00194 and 0.00197 / 0.00127, 1024 0.00202 / 0.00127, 512 0.00216 / 0.00138
  // (docs/BENCHMARKS.md, session 39).
  static constexpr uint32_t kCpuChainsPerUnit = 1024;
  // Chain c's start is the bootstrap path whose cumulative target interval holds
  // (c + u) / chains (systematic resampling); empty when every target is 0.
  static std::vector<uint32_t> resample(const std::vector<float>& targets, uint32_t chains, double u);
  // Chains per path length for normalisations b (largest remainders of chains * b_d / sum b),
  // with at least one for every length of b_d > 0 while chains allow (a length without
  // chains would lose its light); all zero when every b_d is 0.
  static std::vector<uint32_t> allocate(const std::vector<double>& b, uint32_t chains);
  // --mlt-direct auto's R: the share of the bootstrap's target sum that its paths of fewer
  // than `first` bounces carry (path i has i % depths bounces), 0 when all are black.
  static double direct_ratio(const std::vector<float>& target, uint32_t depths, uint32_t first);
  // pssmlt's auto R, whose bootstrap paths leave bounces 0 and 1 out: the same share from
  // b_direct, the direct light's mean target over the film (sampled_direct_b, after its first
  // samples), and the chains' b.
  static double direct_share(double b_direct, double b_chains);
  // The tile target's weight per pixel: the image's mean luminance over its tile's mean
  // (tiles of tile x tile pixels), both estimated from the bootstrap's luminance targets and
  // pixels (path i has i % depths bounces), the tile's mean floored at 0.3 of the image's,
  // raised to `exponent` (1: every tile as often as any other; 0: the luminance target).
  static std::vector<float> tile_importance(const std::vector<float>& target,
                                            const std::vector<uint32_t>& pixel, uint32_t depths,
                                            uint32_t width, uint32_t height, uint32_t tile,
                                            double exponent);
  // The tile target's exponent (tile_importance): bright tiles keep some of their luminance's
  // pull. On the door-ajar scene a tile's relative error per mutation grows with its
  // brightness (the bright strip seen through the gap, lit by long paths few chains reach),
  // so evening the tiles out fully (exponent 1) left most of the image's error there
  // (docs/concepts/metropolis.md, "The target").
  static constexpr double kTileExponent = 0.65;

 private:
  uint32_t chains_for(const dev::RenderParams& params, const Film& film) const;
  // The launch parameters the bootstrap and the chains share, and importance 1 everywhere.
  void set_up(const dev::RenderParams& params, const Film& film);

  const cl::Context& ctx_;
  MltConfig config_;
  cl::Program program_;
  // One kernel, mlt_begin, in two launches: the bootstrap's paths and the chains' start.
  cl::Kernel bootstrap_kernel_, start_kernel_, mutate_kernel_;
  const cl::Kernel& bind_bootstrap(const cl::Buffer& targets, const cl::Buffer& pixels, Film& film);
  // starting 1: the chains' start from the bootstrap; 2: a restart from the pools.
  const cl::Kernel& bind_start(cl_uint starting, const cl::Buffer& starts, Film& film);
  uint32_t dims_for(const dev::RenderParams& params) const;
  // Path lengths the chains sample: max_depth + 1 (mmlt) or 1 (pssmlt).
  uint32_t depths_for(const dev::RenderParams& params) const;

  // Per path length, targets' sums (in double) and counts.
  struct TargetSums {
    explicit TargetSums(size_t depths = 0) : sum(depths, 0.0), sum_sq(depths, 0.0), count(depths, 0) {}
    void add(const TargetSums& other, size_t depth);
    std::vector<double> sum, sum_sq;
    std::vector<uint64_t> count;
  };
  // Each length's pool of large steps as the chains' MltLargeSteps hold it.
  TargetSums pools(const std::vector<dev::MltLargeSteps>& large) const;
  // b, its standard error and per-length figures into stats, from the bootstrap's targets,
  // the pools the restarts took and the pools as large_ holds them now.
  void set_b(MetropolisStats& stats) const;
  // Restarts the chains of each length whose pool of large steps has grown kRestartGrowth
  // times the pool (or bootstrap) they started from: b_d becomes the pool's mean, every chain
  // of the length starts again from a proposal of the pool drawn in proportion to its target,
  // and the pool starts empty.
  void restart_from_pools(Film& film);
  // This pass's direct light (--mlt-direct): the samples per pixel it owes (pt_render's, into
  // direct_film_), then the film's sums set to all of them so far, scaled (mlt_add_direct).
  void direct_pass(const dev::RenderParams& params, Film& film);
  // The direct light's launch parameters: pt cut at one bounce, drawing its camera samples
  // from the pixel filter, with this device's seed.
  dev::RenderParams direct_params(const dev::RenderParams& params) const;
  // direct_film_, the size of the film, once.
  void make_direct_film(const Film& film);
  // The direct light's samples so far as a target's mean over the film: their per-pixel mean
  // luminance times the pixel's tile weight (1 with the luminance target), averaged.
  double sampled_direct_b() const;

  cl::Buffer params_, mlt_params_, depths_, importance_;
  cl::Buffer chains_, coords_;
  cl::Buffer large_;              // MltLargeSteps per chain: its pool since the last restart
  TargetSums bootstrap_sums_;     // the bootstrap's targets that estimate b (the tile target's half)
  TargetSums retired_;            // the pools the restarts have taken
  std::vector<uint32_t> chain_depth_;  // each chain's path length (mmlt), 0 (pssmlt)
  std::vector<dev::MltDepth> norm_;    // what depths_ holds
  bool launched_ = false;         // mlt_mutate has run: large_ holds pools
  uint32_t restarts_ = 0;         // lengths restarted, all restarts together
  std::vector<uint64_t> start_count_;  // per length: the paths of the pool its chains started from
  std::vector<uint64_t> mutations_;    // per length: its chains' proposals since they started
  cl::Buffer unused_;  // 4 bytes: mlt_begin's arguments that one launch does not use
  // The direct light rendered apart (null: the chains sample it): pt_render, its own sums,
  // and the kernel that adds them to the film.
  std::unique_ptr<MegakernelIntegrator> direct_;
  std::unique_ptr<Film> direct_film_;
  cl::Kernel add_direct_kernel_;
  uint32_t first_depth_ = 0;  // mmlt: the chains' shortest path length, 2 with direct_, else 0
  bool direct_ratio_pending_ = false;  // pssmlt with auto: R waits for the first direct samples
  uint64_t direct_mutations_ = 0;  // mutations per pixel this device has rendered (direct_)
  dev::MltParams mlt_{};
  bool started_ = false;
  bool dark_ = false;  // every bootstrap path was black: nothing to mutate
  MetropolisStats stats_;
  cl_uint bootstrap_arg_ = 0, start_arg_ = 0, mutate_arg_ = 0;
};

}  // namespace clpt
