#include "integrators/metropolis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "cl/programs.h"
#include "shared/luminance.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

static_assert(sizeof(dev::MltChain) == 64, "MltChain should stay 64 bytes");
static_assert(sizeof(dev::PssCoord) == 16, "PssCoord should stay 16 bytes");
static_assert(sizeof(dev::MltParams) == 64, "MltParams should stay 64 bytes");
static_assert(sizeof(dev::MltDepth) == 8, "MltDepth is two floats");
static_assert(sizeof(dev::MltLargeSteps) == 32, "MltLargeSteps is eight words");

namespace {

// The chains' state budget when --mlt-chains is not given (as bdpt's light vertex buffer).
constexpr size_t kDefaultChainBudget = size_t(256) << 20;
constexpr uint32_t kMaxDefaultChains = 65536;
// The tile target's floor on a tile's mean, as a fraction of the image's: a tile the
// bootstrap saw dark gets at most (1 / 0.3)^kTileExponent times the weight of an average one.
// On the door-ajar scene at 20 s (tiles of 8, exponent 1) relMSE was 0.0084, 0.0088, 0.0071,
// 0.0074 and 0.0077 for floors of 0.03, 0.1, 0.3, 0.5 and 1 (one run each), 0.0133 with the
// luminance target.
constexpr double kImportanceFloor = 0.3;
// A path length's chains restart when its pool of large steps has grown to this many times the
// pool (or bootstrap) they last started from: segments of geometrically growing length, so
// that the last ones, most of a long render, splat with a b from most of its large steps.
// Door ajar (128x128, 3 seeds at 20 s, 2 at 60 s, docs/BENCHMARKS.md session 36): relMSE
// 0.0077 / 0.00276 without restarts, 0.0075 / - for 2, 0.0071 / 0.00256 for 4, - / 0.00268
// for 8; restarting from every pool the bootstrap's size, 0.0081 at 20 s (each restart
// clusters chains on the pool's brightest proposals anew).
constexpr double kRestartGrowth = 4.0;

// splitmix64's finaliser: 64 well-mixed bits from a seed.
uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// A uniform double in [0, 1) from a seed: the one random number of the host's resampling.
double seeded_unit(uint64_t x) { return double(splitmix64(x) >> 11) * 0x1.0p-53; }

// The settings' checks, before the program is built (a usage error should not wait for it).
const MltConfig& checked(const MltConfig& c) {
  if (!(c.large_step >= 0.0f && c.large_step <= 1.0f))
    throw Error(ExitCode::Usage, "--mlt-large-step must be in [0, 1]");
  if (!(c.sigma > 0.0f) || !std::isfinite(c.sigma))
    throw Error(ExitCode::Usage, "--mlt-sigma must be a positive number");
  if (c.bootstrap == 0) throw Error(ExitCode::Usage, "--mlt-bootstrap must be at least 1");
  if (c.bootstrap > (1u << 26)) throw Error(ExitCode::Usage, "--mlt-bootstrap must be at most 2^26");
  // The tile target splits the bootstrap's rounds in two (weights, then b and the starts).
  if (c.importance_tile > 0 && c.bootstrap < 2)
    throw Error(ExitCode::Usage, "mlt: --mlt-target tile needs --mlt-bootstrap of at least 2");
  if (!(c.direct >= 0.0f || c.direct == kMltDirectAuto) || !std::isfinite(c.direct))
    throw Error(ExitCode::Usage, "--mlt-direct must be auto or a number >= 0");
  return c;
}

size_t chain_bytes(uint32_t dims) { return sizeof(dev::MltChain) + size_t(dims) * sizeof(dev::PssCoord); }

}  // namespace

Metropolis::Metropolis(const cl::Context& ctx, const SceneBuffers& scene, const MltConfig& config)
    : ctx_(ctx),
      config_(checked(config)),
      program_(ctx, config_.multiplexed ? programs::kMmlt : programs::kPssmlt),
      bootstrap_kernel_(program_, "mlt_begin"),
      start_kernel_(program_, "mlt_begin"),
      mutate_kernel_(program_, "mlt_mutate"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      mlt_params_(ctx, sizeof(dev::MltParams), CL_MEM_READ_ONLY, nullptr, "Metropolis parameters"),
      depths_(ctx, sizeof(dev::MltDepth), CL_MEM_READ_ONLY, nullptr, "Metropolis normalisations"),
      importance_(ctx, sizeof(float), CL_MEM_READ_ONLY, nullptr, "Metropolis importance"),
      chains_(ctx, sizeof(dev::MltChain), CL_MEM_READ_WRITE, nullptr, "Metropolis chains"),
      coords_(ctx, sizeof(dev::PssCoord), CL_MEM_READ_WRITE, nullptr, "primary sample vectors"),
      unused_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "mlt_begin's unused buffers"),
      add_direct_kernel_(program_, "mlt_add_direct") {
  if (config_.direct != 0.0f)
    direct_ = std::make_unique<MegakernelIntegrator>(ctx, scene, "direct", programs::kPt, "pt_render");
  bootstrap_arg_ = scene.bind(bootstrap_kernel_, 0);
  start_arg_ = scene.bind(start_kernel_, 0);
  mutate_arg_ = scene.bind(mutate_kernel_, 0);
}

uint32_t Metropolis::default_chains(size_t pixels, uint32_t dims, size_t budget_bytes, uint32_t cap) {
  const size_t fit = budget_bytes / chain_bytes(dims);
  return static_cast<uint32_t>(std::max<size_t>(1, std::min({pixels, size_t(cap), fit})));
}

uint32_t Metropolis::default_chain_cap(bool cpu, uint32_t compute_units) {
  if (!cpu) return kMaxDefaultChains;
  return std::min(kMaxDefaultChains, kCpuChainsPerUnit * std::max(compute_units, 1u));
}

std::vector<uint32_t> Metropolis::resample(const std::vector<float>& targets, uint32_t chains,
                                           double u) {
  std::vector<double> cumulative(targets.size());
  double total = 0.0;
  for (size_t i = 0; i < targets.size(); ++i) cumulative[i] = total += std::max(0.0f, targets[i]);
  if (!(total > 0.0)) return {};
  std::vector<uint32_t> start(chains);
  for (uint32_t c = 0; c < chains; ++c) {
    const double x = (double(c) + u) / double(chains) * total;
    // The first path whose cumulative target exceeds x: its interval holds x, and it is not
    // empty, so the path's target is > 0.
    const size_t i = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
    start[c] = static_cast<uint32_t>(std::min(i, targets.size() - 1));
  }
  return start;
}

std::vector<uint32_t> Metropolis::allocate(const std::vector<double>& b, uint32_t chains) {
  std::vector<uint32_t> n(b.size(), 0);
  double total = 0.0;
  for (double x : b) total += std::max(0.0, x);
  if (!(total > 0.0)) return n;
  std::vector<double> remainder(b.size());
  uint32_t given = 0;
  for (size_t d = 0; d < b.size(); ++d) {
    const double quota = std::max(0.0, b[d]) / total * double(chains);
    n[d] = static_cast<uint32_t>(std::floor(quota));
    remainder[d] = quota - double(n[d]);
    given += n[d];
  }
  std::vector<size_t> order(b.size());
  for (size_t d = 0; d < order.size(); ++d) order[d] = d;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t x, size_t y) { return remainder[x] > remainder[y]; });
  for (size_t i = 0; given < chains && i < order.size(); ++i, ++given) ++n[order[i]];
  // Lengths that carry light but got no chain take one from the length with the most.
  for (size_t d = 0; d < b.size(); ++d) {
    if (n[d] > 0 || !(b[d] > 0.0)) continue;
    const size_t most = size_t(std::max_element(n.begin(), n.end()) - n.begin());
    if (n[most] < 2) break;
    --n[most];
    n[d] = 1;
  }
  return n;
}

double Metropolis::direct_ratio(const std::vector<float>& target, uint32_t depths, uint32_t first) {
  double direct = 0.0, all = 0.0;
  for (size_t i = 0; i < target.size(); ++i) {
    all += target[i];
    if (i % depths < first) direct += target[i];
  }
  return all > 0.0 ? direct / all : 0.0;
}

double Metropolis::direct_share(double b_direct, double b_chains) {
  return b_direct + b_chains > 0.0 ? b_direct / (b_direct + b_chains) : 0.0;
}

double Metropolis::sampled_direct_b() const {
  const FilmSums sums = direct_film_->read();
  // The weights the chains' targets carry: the tile weights, or 1 everywhere (set_up).
  const std::vector<float> w = importance_.read_vector<float>(sums.sum.size());
  const double k = double(std::max<uint64_t>(stats_.direct_samples, 1));
  double b = 0.0;
  for (size_t p = 0; p < sums.sum.size(); ++p) {
    const std::array<float, 4>& s = sums.sum[p];
    const double y = CLPT_LUMINANCE_R * s[0] + CLPT_LUMINANCE_G * s[1] + CLPT_LUMINANCE_B * s[2];
    b += double(w[p]) * y / k;
  }
  return sums.sum.empty() ? 0.0 : b / double(sums.sum.size());
}

std::vector<float> Metropolis::tile_importance(const std::vector<float>& target,
                                               const std::vector<uint32_t>& pixel, uint32_t depths,
                                               uint32_t width, uint32_t height, uint32_t tile,
                                               double exponent) {
  const uint32_t tx = (width + tile - 1) / tile, ty = (height + tile - 1) / tile;
  std::vector<double> sum(size_t(tx) * ty, 0.0);
  std::vector<uint32_t> area(sum.size(), 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) ++area[(y / tile) * tx + x / tile];
  for (size_t i = 0; i < target.size(); ++i) {
    const uint32_t p = pixel[i];
    sum[((p / width) / tile) * tx + (p % width) / tile] += target[i];
  }
  // Tile j's mean luminance: sum_d (1 / B) sum_{i of length d in j} I_i / P(j), P(j) the
  // tile's share of the film; the paths per length B = target.size() / depths.
  const double per_length = double(target.size()) / double(depths);
  const double pixels = double(width) * height;
  double image = 0.0;
  std::vector<double> mean(sum.size());
  for (size_t j = 0; j < sum.size(); ++j) {
    mean[j] = sum[j] / per_length * pixels / double(area[j]);
    image += sum[j] / per_length;
  }
  const double floor = kImportanceFloor * image;
  std::vector<float> w(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      w[size_t(y) * width + x] =
          float(std::pow(image / std::max(mean[(y / tile) * tx + x / tile], floor), exponent));
  return w;
}

uint32_t Metropolis::dims_for(const dev::RenderParams& params) const {
  return config_.multiplexed ? MMLT_DIMS(params.max_depth) : PSS_DIMS(params.max_depth);
}

uint32_t Metropolis::chains_for(const dev::RenderParams& params, const Film& film) const {
  const cl::DeviceInfo& dev = ctx_.device();
  return config_.chains ? config_.chains
                        : default_chains(film.pixels(), dims_for(params), kDefaultChainBudget,
                                         default_chain_cap(dev.is_cpu(), dev.compute_units));
}

// mlt_begin's two launches (kernels/integrators/mlt.cl): each binds the buffers the other
// writes to a placeholder the kernel leaves alone.
const cl::Kernel& Metropolis::bind_bootstrap(const cl::Buffer& targets, const cl::Buffer& pixels,
                                        Film& film) {
  bootstrap_kernel_.args(bootstrap_arg_, params_, mlt_params_, cl_uint(0), unused_, importance_,
                         targets, pixels, unused_, unused_, unused_, film.ray_counts());
  return bootstrap_kernel_;
}

const cl::Kernel& Metropolis::bind_start(cl_uint starting, const cl::Buffer& starts, Film& film) {
  start_kernel_.args(start_arg_, params_, mlt_params_, starting, starts, importance_, unused_,
                     unused_, chains_, coords_, starting == 2 ? large_ : unused_, film.ray_counts());
  return start_kernel_;
}

void Metropolis::warm_up(const dev::RenderParams& params, Film& film) {
  // Every kernel once over as many work-items as its real launches (PoCL compiles a
  // work-group function per grid size class at the first launch of each), with no
  // bootstrap paths and no chains in the parameters: each work-item returns at once.
  dev::MltParams none{};
  params_.write(&params, sizeof(params));
  mlt_params_.write(&none, sizeof(none));
  // No work-item reads or writes a buffer here, so the placeholder stands for all of them.
  const uint32_t chains = chains_for(params, film);
  bind_bootstrap(unused_, unused_, film).launch(ctx_, config_.bootstrap);
  bind_start(1, unused_, film).launch(ctx_, chains);
  mutate_kernel_.args(mutate_arg_, params_, mlt_params_, depths_, importance_, chains_, coords_,
                      film.splat(), unused_, film.ray_counts());
  mutate_kernel_.launch(ctx_, chains);
  if (direct_) {
    make_direct_film(film);
    direct_->warm_up(direct_params(params), *direct_film_);
    add_direct_kernel_.args(0, film.sum(), film.ray_counts(), direct_film_->sum(),
                            direct_film_->ray_counts(), 0.0f, cl_uint(0));
    add_direct_kernel_.launch(ctx_, film.pixels());
  }
  ctx_.finish();
}

uint32_t Metropolis::depths_for(const dev::RenderParams& params) const {
  return config_.multiplexed ? params.max_depth + 1u : 1u;
}

uint64_t Metropolis::setup_items(const dev::RenderParams& params) const {
  return uint64_t(config_.bootstrap) * depths_for(params);
}

void Metropolis::set_up(const dev::RenderParams& params, const Film& film) {
  mlt_.dims = dims_for(params);
  mlt_.chains = chains_for(params, film);
  const bool gpu = ctx_.device().is_gpu();
  mlt_.dim_stride = gpu ? mlt_.chains : 1u;
  mlt_.chain_stride = gpu ? 1u : mlt_.dims;
  mlt_.depths = depths_for(params);
  // With the direct light apart, the chains sample bounces 2 on (none where max_depth < 2):
  // mmlt gives the shorter lengths no chains, pssmlt's paths leave those bounces out.
  const uint32_t first = direct_ ? std::min(2u, params.max_depth + 1u) : 0u;
  first_depth_ = config_.multiplexed ? first : 0u;
  mlt_.first_depth = config_.multiplexed ? 0u : first;
  // The tile weights' paths count every depth: the weights follow the whole image.
  mlt_.weight_rounds = config_.importance_tile > 0 ? 1u : 0u;
  if (direct_) make_direct_film(film);
  const uint64_t paths = setup_items(params);
  if (paths > 0xffffffffull)
    throw Error(ExitCode::Usage, "mlt: --mlt-bootstrap times the path lengths (--max-depth + 1) "
                                 "exceeds 2^32 paths");
  mlt_.bootstrap = static_cast<uint32_t>(paths);
  mlt_.large_step = config_.large_step;
  mlt_.sigma = config_.sigma;
  mlt_.seed = params.seed;
  // Several devices each run chains of their own from the same bootstrap: their chains'
  // random numbers are keyed past the devices' before them (mod 2^32: a key).
  mlt_.chain_base = static_cast<uint32_t>(uint64_t(device_index()) * mlt_.chains);
  params_.write(&params, sizeof(params));
  // The bootstrap's paths with the plain luminance target (importance 1 everywhere).
  importance_ = cl::Buffer::from_vector(ctx_, std::vector<float>(film.pixels(), 1.0f),
                                        CL_MEM_READ_ONLY, "Metropolis importance");
}

std::string Metropolis::setup_part(const dev::RenderParams& params, Film& film, uint64_t first,
                                   uint64_t count) {
  const auto t0 = Clock::now();
  set_up(params, film);
  // Its share of the bootstrap's paths: the first and the count (two u64), then their targets
  // and their pixels.
  const size_t head = 2 * sizeof(uint64_t);
  std::string part(head + size_t(count) * (sizeof(float) + sizeof(uint32_t)), '\0');
  std::memcpy(part.data(), &first, sizeof(first));
  std::memcpy(part.data() + sizeof(first), &count, sizeof(count));
  if (count > 0) {
    mlt_.bootstrap_first = static_cast<uint32_t>(first);
    mlt_.bootstrap_count = static_cast<uint32_t>(count);
    mlt_params_.write(&mlt_, sizeof(mlt_));
    cl::Buffer targets(ctx_, size_t(count) * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                       "bootstrap targets");
    cl::Buffer pixels(ctx_, size_t(count) * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                      "bootstrap pixels");
    bind_bootstrap(targets, pixels, film).launch(ctx_, count);
    targets.read(part.data() + head, size_t(count) * sizeof(float));
    pixels.read(part.data() + head + size_t(count) * sizeof(float), size_t(count) * sizeof(uint32_t));
  }
  stats_.bootstrap_seconds = seconds_since(t0);
  return part;
}

void Metropolis::setup_finish(const dev::RenderParams& params, Film& film, const std::string& parts) {
  const auto t0 = Clock::now();
  started_ = true;
  const uint32_t depths = mlt_.depths;
  // Every device's part (setup_part), each placed at its paths; together they must cover
  // every path once.
  std::vector<float> target(mlt_.bootstrap);
  std::vector<uint32_t> pixel(mlt_.bootstrap);
  uint64_t covered = 0;
  for (size_t at = 0; at < parts.size();) {
    uint64_t first = 0, count = 0;
    if (parts.size() - at < 2 * sizeof(uint64_t)) break;
    std::memcpy(&first, parts.data() + at, sizeof(first));
    std::memcpy(&count, parts.data() + at + sizeof(first), sizeof(count));
    at += 2 * sizeof(uint64_t);
    if (first + count > mlt_.bootstrap || parts.size() - at < count * (sizeof(float) + sizeof(uint32_t)))
      break;
    std::memcpy(target.data() + first, parts.data() + at, count * sizeof(float));
    at += count * sizeof(float);
    std::memcpy(pixel.data() + first, parts.data() + at, count * sizeof(uint32_t));
    at += count * sizeof(uint32_t);
    covered += count;
  }
  if (covered != mlt_.bootstrap)
    throw std::logic_error("mlt: the devices' bootstrap parts do not cover its paths");
  // With the tile target, the even rounds of paths (i / depths even) estimate the image for
  // the weights and the odd ones, independent of them, give b and the start states: weights
  // from the same paths would make b a ratio of correlated sums, low where a tile's light
  // comes in rare large samples (the caustic scene's image came out 3.5 % dark that way).
  const bool tiles = config_.importance_tile > 0;
  auto for_weights = [&](size_t i) { return tiles && (i / depths) % 2 == 0; };
  if (tiles) {
    std::vector<float> t_w;
    std::vector<uint32_t> p_w;
    for (size_t i = 0; i < target.size(); ++i)
      if (for_weights(i)) {
        t_w.push_back(target[i]);
        p_w.push_back(pixel[i]);
      }
    const std::vector<float> w = tile_importance(t_w, p_w, depths, params.width, params.height,
                                                 config_.importance_tile, kTileExponent);
    for (size_t i = 0; i < target.size(); ++i) target[i] *= w[pixel[i]];
    importance_ = cl::Buffer::from_vector(ctx_, w, CL_MEM_READ_ONLY, "Metropolis importance");
  }

  // Path i has i % depths bounces: each length's targets (and their paths), their mean b_d
  // and its error.
  std::vector<std::vector<float>> by_depth(depths);
  std::vector<std::vector<uint32_t>> path_of(depths);
  // Lengths below first_depth_ (the direct light, rendered apart) get no paths: b_d = 0 and
  // no chains. The tile weights above still come from every length: they follow the whole
  // image, whose relative error the chains' share of it adds to.
  std::vector<float> b_paths;
  for (size_t i = 0; i < target.size(); ++i) {
    if (for_weights(i)) continue;
    b_paths.push_back(target[i]);
    if (i % depths < first_depth_) continue;
    by_depth[i % depths].push_back(target[i]);
    path_of[i % depths].push_back(uint32_t(i));
  }
  if (direct_) {
    // b_paths holds every depths-th path of each round alike, so path j has j % depths bounces.
    // pssmlt's paths leave bounces 0 and 1 out: its auto ratio waits for the direct light's
    // first samples (direct_pass).
    if (config_.direct != kMltDirectAuto)
      stats_.direct_ratio = double(config_.direct);
    else if (config_.multiplexed)
      stats_.direct_ratio = direct_ratio(b_paths, depths, first_depth_);
    else
      direct_ratio_pending_ = true;
  }
  bootstrap_sums_ = TargetSums(depths);
  retired_ = TargetSums(depths);
  for (uint32_t d = 0; d < depths; ++d) {
    for (float t : by_depth[d]) {
      bootstrap_sums_.sum[d] += t;
      bootstrap_sums_.sum_sq[d] += double(t) * t;
    }
    bootstrap_sums_.count[d] = by_depth[d].size();
  }
  set_b(stats_);
  stats_.b_bootstrap = stats_.b;
  start_count_ = bootstrap_sums_.count;
  mutations_.assign(depths, 0);
  stats_.bootstrap_paths = mlt_.bootstrap;
  stats_.chains = mlt_.chains;
  stats_.dims = mlt_.dims;

  // Chains per length, then each length's starts resampled from its own paths, one run of
  // chains per length (a GPU warp's chains then trace paths of one length).
  std::vector<uint32_t> chains_of = allocate(stats_.b_by_depth, mlt_.chains);
  std::vector<uint32_t> start;
  start.reserve(mlt_.chains);
  // The resampling's offset: the first device's from the seed alone, the others' shifted.
  const double u = seeded_unit(uint64_t(params.seed) + (uint64_t(device_index()) << 32));
  for (uint32_t d = 0; d < depths; ++d) {
    if (chains_of[d] == 0) continue;
    for (uint32_t j : resample(by_depth[d], chains_of[d], u)) start.push_back(path_of[d][j]);
  }
  if (start.empty()) {
    // Nothing for chains to sample: the direct light apart is then the image (max_depth < 2,
    // or no light past one bounce), unless no bootstrap path found light at all.
    // (pssmlt's paths do not see the direct light apart, which may still be there.)
    if ((config_.multiplexed || !direct_) &&
        std::none_of(b_paths.begin(), b_paths.end(), [](float t) { return t > 0.0f; }))
      log::warn("mlt: all " + std::to_string(mlt_.bootstrap) + " bootstrap paths carry no light; "
                "the image stays black");
    dark_ = true;
    stats_.bootstrap_seconds += seconds_since(t0);
    return;
  }
  if (!config_.resample)
    for (uint32_t c = 0; c < mlt_.chains; ++c) start[c] = c % mlt_.bootstrap;

  // What each length's chains splat with: its b_d and the share of the chains it has.
  std::vector<uint32_t> count(depths, 0);
  chain_depth_.resize(start.size());
  for (size_t c = 0; c < start.size(); ++c) ++count[chain_depth_[c] = start[c] % depths];
  norm_.assign(depths, dev::MltDepth{});
  for (uint32_t d = 0; d < depths; ++d) {
    norm_[d].b = float(stats_.b_by_depth[d]);
    norm_[d].chain_scale = count[d] ? float(double(mlt_.chains) / double(count[d])) : 0.0f;
  }
  stats_.chains_by_depth = count;
  depths_ = cl::Buffer::from_vector(ctx_, norm_, CL_MEM_READ_ONLY, "Metropolis normalisations");
  large_ = cl::Buffer::from_vector(ctx_, std::vector<dev::MltLargeSteps>(mlt_.chains),
                                   CL_MEM_READ_WRITE, "large steps' pools");

  chains_ = cl::Buffer(ctx_, size_t(mlt_.chains) * sizeof(dev::MltChain), CL_MEM_READ_WRITE,
                       nullptr, "Metropolis chains");
  coords_ = cl::Buffer(ctx_, size_t(mlt_.chains) * mlt_.dims * sizeof(dev::PssCoord),
                       CL_MEM_READ_WRITE, nullptr, "primary sample vectors");
  stats_.device_bytes = chains_.size() + coords_.size() + depths_.size() + large_.size();
  const cl::Buffer starts = cl::Buffer::from_vector(ctx_, start, CL_MEM_READ_ONLY, "chain starts");
  mlt_params_.write(&mlt_, sizeof(mlt_));
  bind_start(1, starts, film).launch(ctx_, mlt_.chains);
  ctx_.finish();
  stats_.bootstrap_seconds += seconds_since(t0);
  log::verbose("mlt: b = " + std::to_string(stats_.b) + " +- " +
               std::to_string(stats_.b_standard_error) + " from " +
               std::to_string(mlt_.bootstrap) + " paths, " + std::to_string(mlt_.chains) +
               " chains of " + std::to_string(mlt_.dims) + " dimensions");
}

void Metropolis::render_pass(const dev::RenderParams& params, Film& film) {
  if (!film.splats()) throw Error(ExitCode::Usage, "Metropolis needs a film with splats");
  // The bootstrap, where the renderer did not share it out (setup_items) before this pass.
  if (!started_) setup_finish(params, film, setup_part(params, film, 0, setup_items(params)));
  if (direct_) direct_pass(params, film);
  if (dark_) return;
  if (launched_ && config_.restart) restart_from_pools(film);
  // spp mutations per pixel in all, spread over the chains; the scale makes up for the
  // rounding, so that the film's division by spp is exact.
  const uint64_t total = uint64_t(params.samples_per_pass) * film.pixels();
  const uint64_t per_chain = (total + mlt_.chains - 1) / mlt_.chains;
  if (per_chain > 0xffffffffull)
    throw Error(ExitCode::Usage, "mlt: more than 2^32 mutations per chain in one pass; use more "
                                 "--mlt-chains");
  mlt_.mutations = static_cast<uint32_t>(per_chain);
  mlt_.splat_scale = float(double(total) / (double(per_chain) * mlt_.chains));
  params_.write(&params, sizeof(params));
  mlt_params_.write(&mlt_, sizeof(mlt_));
  mutate_kernel_.args(mutate_arg_, params_, mlt_params_, depths_, importance_, chains_, coords_,
                      film.splat(), large_, film.ray_counts());
  mutate_kernel_.launch(ctx_, mlt_.chains);
  launched_ = true;
  for (size_t d = 0; d < mutations_.size(); ++d)
    mutations_[d] += per_chain * stats_.chains_by_depth[d];
}

void Metropolis::make_direct_film(const Film& film) {
  if (!direct_film_) direct_film_ = std::make_unique<Film>(ctx_, film.width(), film.height());
}

dev::RenderParams Metropolis::direct_params(const dev::RenderParams& params) const {
  dev::RenderParams direct = params;
  direct.max_depth = std::min(params.max_depth, 1u);
  direct.spp_total = 0;
  // The chains splat through the pixel filter (filter_splat); pt's samples are drawn from it
  // instead (filter importance sampling), which gives the same filtered image.
  direct.filter_splat = 0u;
  // The first device's stream is the seed's (so that R = 1 renders what `direct` renders),
  // the others' keyed apart by their index.
  if (device_index() > 0)
    direct.seed = static_cast<uint32_t>(
        splitmix64(uint64_t(params.seed) ^ (uint64_t(device_index()) << 32)) >> 32);
  return direct;
}

void Metropolis::direct_pass(const dev::RenderParams& params, Film& film) {
  // K = max(1, round(R N)) direct samples per pixel after N mutations per pixel: this pass
  // takes what K has grown by (often none in a short pass when R is small; always the first).
  direct_mutations_ += params.samples_per_pass;
  const uint64_t want = std::max<uint64_t>(
      1, static_cast<uint64_t>(std::llround(stats_.direct_ratio * double(direct_mutations_))));
  if (want > stats_.direct_samples) {
    // Samples K .. want - 1 of this device's own stream.
    dev::RenderParams direct = direct_params(params);
    direct.sample_offset = static_cast<uint32_t>(stats_.direct_samples);
    direct.samples_per_pass = static_cast<uint32_t>(want - stats_.direct_samples);
    direct_->render_pass(direct, *direct_film_);
    stats_.direct_samples = want;
  }
  if (direct_ratio_pending_) {
    stats_.direct_ratio = direct_share(sampled_direct_b(), stats_.b);
    direct_ratio_pending_ = false;
  }
  add_direct_kernel_.args(0, film.sum(), film.ray_counts(), direct_film_->sum(),
                          direct_film_->ray_counts(),
                          float(double(direct_mutations_) / double(stats_.direct_samples)),
                          cl_uint(film.pixels()));
  add_direct_kernel_.launch(ctx_, film.pixels());
}

void Metropolis::TargetSums::add(const TargetSums& other, size_t d) {
  sum[d] += other.sum[d];
  sum_sq[d] += other.sum_sq[d];
  count[d] += other.count[d];
}

Metropolis::TargetSums Metropolis::pools(const std::vector<dev::MltLargeSteps>& large) const {
  TargetSums s(norm_.size());
  for (size_t c = 0; c < large.size(); ++c) {
    const uint32_t d = chain_depth_[c];
    s.sum[d] += double(large[c].sum) - double(large[c].compensation);
    s.sum_sq[d] += large[c].sum_sq;
    s.count[d] += large[c].count;
  }
  return s;
}

void Metropolis::restart_from_pools(Film& film) {
  // Read the pools only when some length's may have grown enough: its chains have proposed
  // about large_step times their mutations as large steps.
  bool due = false;
  for (size_t d = 0; d < norm_.size(); ++d)
    due |= stats_.chains_by_depth[d] > 0 &&
           double(mlt_.large_step) * double(mutations_[d]) >= kRestartGrowth * double(start_count_[d]);
  if (!due) return;
  std::vector<dev::MltLargeSteps> large = large_.read_vector<dev::MltLargeSteps>(mlt_.chains);
  const TargetSums pool = pools(large);
  std::vector<uint32_t> start(mlt_.chains, ~0u);
  bool any = false;
  for (size_t d = 0; d < norm_.size(); ++d) {
    // A pool kRestartGrowth times the one the chains started from: b_d and the start states
    // of each segment come from one pool (together they are unbiased, as the bootstrap's
    // are), and the segments, growing geometrically, put most of the render on the largest.
    if (double(pool.count[d]) < kRestartGrowth * double(start_count_[d]) || !(pool.sum[d] > 0.0))
      continue;
    std::vector<uint32_t> chains;
    std::vector<float> weight;
    for (uint32_t c = 0; c < mlt_.chains; ++c)
      if (chain_depth_[c] == d) {
        chains.push_back(c);
        weight.push_back(std::max(0.0f, large[c].sum - large[c].compensation));
      }
    if (chains.empty()) continue;
    // Chain j's pick is each of its proposals in proportion to the target, and chain j is
    // drawn in proportion to its pool's sum: each restart is a proposal of the whole pool in
    // proportion to its target, as the bootstrap's resampling draws the first starts.
    const double u = seeded_unit(uint64_t(mlt_.seed) + (uint64_t(device_index()) << 32) +
                                 (uint64_t(restarts_ + 1) << 40));
    const std::vector<uint32_t> picks = resample(weight, uint32_t(chains.size()), u);
    if (picks.empty()) continue;
    // A chain drawn k times gives its picks 0, 1, ... (independent draws from its pool), so
    // that its restarts do not all start from one state while it has picks left.
    std::vector<uint32_t> used(chains.size(), 0);
    for (size_t j = 0; j < chains.size(); ++j)
      start[chains[j]] = chains[picks[j]] * MLT_PICKS + used[picks[j]]++ % MLT_PICKS;
    norm_[d].b = float(pool.sum[d] / double(pool.count[d]));
    start_count_[d] = pool.count[d];
    mutations_[d] = 0;
    retired_.add(pool, d);
    for (uint32_t c : chains) large[c] = dev::MltLargeSteps{};
    ++restarts_;
    any = true;
  }
  if (!any) return;
  depths_.write(norm_.data(), norm_.size() * sizeof(dev::MltDepth));
  const cl::Buffer starts = cl::Buffer::from_vector(ctx_, start, CL_MEM_READ_ONLY, "chain restarts");
  bind_start(2, starts, film).launch(ctx_, mlt_.chains);
  // The restart reads the picks first (the queue is in order); then the pools start again.
  large_.write(large.data(), large.size() * sizeof(dev::MltLargeSteps));
  ctx_.finish();
}

void Metropolis::set_b(MetropolisStats& stats) const {
  TargetSums sums = bootstrap_sums_;
  const TargetSums now = launched_ ? pools(large_.read_vector<dev::MltLargeSteps>(mlt_.chains))
                                   : TargetSums(sums.count.size());
  stats.b_large_steps = 0;
  for (size_t d = 0; d < sums.count.size(); ++d) {
    sums.add(retired_, d);
    sums.add(now, d);
    stats.b_large_steps += retired_.count[d] + now.count[d];
  }
  const size_t depths = sums.sum.size();
  stats.b_by_depth.assign(depths, 0.0);
  stats.b_depth_standard_error.assign(depths, 0.0);
  double b = 0.0, variance = 0.0;
  for (size_t d = 0; d < depths; ++d) {
    const double n = double(sums.count[d]), sum = sums.sum[d];
    if (!(n > 0.0)) continue;
    stats.b_by_depth[d] = sum / n;
    b += sum / n;
    const double v = n > 1 ? std::max(0.0, (sums.sum_sq[d] - sum * sum / n) / (n - 1.0)) / n : 0.0;
    stats.b_depth_standard_error[d] = std::sqrt(v);
    variance += v;
  }
  stats.b = b;
  stats.b_standard_error = std::sqrt(variance);
  stats.restarts = restarts_;
}

MetropolisStats Metropolis::metropolis_stats() const {
  MetropolisStats s = stats_;
  if (!started_ || dark_) return s;
  set_b(s);
  for (const dev::MltChain& c : chains_.read_vector<dev::MltChain>(mlt_.chains)) {
    s.large_proposed += c.large_proposed;
    s.large_accepted += c.large_accepted;
    s.small_proposed += c.small_proposed;
    s.small_accepted += c.small_accepted;
  }
  return s;
}

}  // namespace clpt
