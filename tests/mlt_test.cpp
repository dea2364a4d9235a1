// Metropolis light transport (--integrator mlt, host/integrators/metropolis.h).
//   MltStationary     chains on a toy target in primary sample space (tests/kernels/mlt_test.cl):
//                     the histogram of their states is the target (chi-square), including a
//                     coordinate the target reads only on part of the domain (the lazy
//                     updates); no restore on reject, or a wrong acceptance, fail it; the small
//                     steps' normal numbers are standard normal
//   MltResample       the host's systematic resampling of the bootstrap: proportional to the
//                     targets, never a black path; mmlt's chains per path length
//   SphereFurnaceMlt  the image matches the closed form, as a mean and block by block, for
//                     mmlt and pssmlt
//   MmltFurnace       each path length's bootstrap mean b_d is the closed form Le rho^d: every
//                     bdpt strategy mmlt chooses from, weighted and scaled, sums to its length
//   CrossIntegrator   mlt matches the pt reference on the Cornell box (blocks, pixels, image),
//                     mmlt and pssmlt
//   MltPool           a chain's pool of large steps picks proposals in proportion to their
//                     targets (chi-square), and sums them
//   MltRestart        restarts from the pools take b's error away from the image's
//                     brightness, without bias; never restarting keeps it (mmlt)
//   MltStartUp        32 runs of one mutation per pixel average to the reference: the
//                     bootstrap's resampling removes start-up bias; starting the chains at
//                     unweighted bootstrap paths instead fails the same test (mmlt)
//   MltOptions        usage errors
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "integrators/metropolis.h"
#include "options.h"
#include "render/renderer.h"
#include "shared/mlt_types.h"
#include "stats/image_stats.h"
#include "support/block_test.h"
#include "support/chi2.h"
#include "support/device.h"
#include "support/parse_options.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt::mlt_test {
namespace {

// ---- The toy target of tests/kernels/mlt_test.cl, on the host. ----
double toy_g(double u0, double u1) {
  const double dx = u0 - 0.3, dy = u1 - 0.6;
  return 0.2 + std::exp(-(dx * dx + dy * dy) / (2.0 * 0.15 * 0.15));
}
// h(u2) = 0.25 + 1.5 u2^2, the toy target's factor in u2 (read where u0 < 0.5).
constexpr double kToyHIntegral = 0.75;  // of h over [0, 1]

enum ToyRule : uint32_t { kMetropolis = 0, kNoRestore = 1, kSqrtAcceptance = 2 };

std::vector<glm::vec4> toy_chains(uint32_t chains, uint32_t iterations, float large_step,
                                  float sigma, ToyRule rule, uint32_t seed) {
  cl::Context& ctx = test::device_context();
  cl::Buffer coords(ctx, size_t(chains) * 4 * sizeof(dev::PssCoord));
  cl::Buffer out(ctx, size_t(chains) * sizeof(glm::vec4));
  cl::Kernel k(test::test_program("kernels/mlt_test.cl"), "mlt_toy_chains");
  k.args(0, coords, chains, iterations, large_step, sigma, uint32_t(rule), seed, out);
  k.launch(ctx, chains);
  return out.read_vector<glm::vec4>(chains);
}

struct ToyFit {
  test::Chi2Result joint;  // (u0, u1) on a 16 x 16 grid
  test::Chi2Result u2;     // u2 where u0 < 0.5, 16 bins
};

ToyFit toy_fit(const std::vector<glm::vec4>& states) {
  constexpr int kBins = 16, kSub = 8;
  // Expected (u0, u1) counts: the marginal g(u0, u1) * (u0 < 0.5 ? integral of h : 1),
  // integrated over each cell by the midpoint rule on kSub x kSub points.
  std::vector<double> mass(kBins * kBins, 0.0);
  double total = 0.0;
  for (int i = 0; i < kBins; ++i)
    for (int j = 0; j < kBins; ++j) {
      double m = 0.0;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) {
          const double u0 = (i + (a + 0.5) / kSub) / kBins, u1 = (j + (b + 0.5) / kSub) / kBins;
          m += toy_g(u0, u1) * (u0 < 0.5 ? kToyHIntegral : 1.0);
        }
      mass[i * kBins + j] = m;
      total += m;
    }
  std::vector<double> observed(kBins * kBins, 0.0), expected(kBins * kBins);
  std::vector<double> observed_u2(kBins, 0.0), expected_u2(kBins);
  size_t left = 0;
  for (const glm::vec4& s : states) {
    const int i = std::clamp(int(s.x * kBins), 0, kBins - 1);
    const int j = std::clamp(int(s.y * kBins), 0, kBins - 1);
    observed[i * kBins + j] += 1.0;
    if (s.x < 0.5f) {
      observed_u2[std::clamp(int(s.z * kBins), 0, kBins - 1)] += 1.0;
      ++left;
    }
  }
  for (size_t c = 0; c < mass.size(); ++c) expected[c] = mass[c] / total * double(states.size());
  for (int b = 0; b < kBins; ++b) {
    const double lo = double(b) / kBins, hi = double(b + 1) / kBins;
    const double integral = 0.25 * (hi - lo) + 0.5 * (hi * hi * hi - lo * lo * lo);
    expected_u2[b] = integral / kToyHIntegral * double(left);
  }
  test::Chi2Options opt;
  opt.alpha = 0.01 / 2.0;  // two statistics per fit
  const auto cell = [](size_t c) { return "cell " + std::to_string(c); };
  return {test::chi2_counts(observed, expected, opt, cell),
          test::chi2_counts(observed_u2, expected_u2, opt, cell)};
}

constexpr uint32_t kToyChains = 20000, kToyIterations = 160;

// From a uniform start, 160 proposals with large steps at 0.3 leave the chains within a
// total variation of about 1e-4 of their stationary law (the independence sampler's rate,
// 1 - 0.3 * min f / max f per step, bounds it), far below what 20 000 states resolve.
TEST(MltStationary, ChainsSampleTheTarget) {
  for (const float sigma : {0.01f, 0.1f}) {
    const ToyFit fit = toy_fit(toy_chains(kToyChains, kToyIterations, 0.3f, sigma, kMetropolis, 11));
    EXPECT_TRUE(fit.joint.passed) << "sigma " << sigma << ": " << fit.joint.report;
    EXPECT_TRUE(fit.u2.passed) << "sigma " << sigma << ": " << fit.u2.report;
    std::cout << "[ figures  ] toy chains sigma " << sigma << ": (u0,u1) " << fit.joint.summary()
              << "; u2 " << fit.u2.summary() << "\n";
  }
}

// Small steps alone (no large step) also keep the target: the Gaussian perturbation is
// symmetric, so Metropolis' rule needs no proposal ratio. A sigma of 0.1 mixes in 160 steps.
TEST(MltStationary, SmallStepsAloneSampleTheTarget) {
  const ToyFit fit = toy_fit(toy_chains(kToyChains, 400, 0.0f, 0.1f, kMetropolis, 12));
  EXPECT_TRUE(fit.joint.passed) << fit.joint.report;
  EXPECT_TRUE(fit.u2.passed) << fit.u2.report;
}

TEST(MltStationary, NotRestoringRejectedProposalsFails) {
  const ToyFit fit = toy_fit(toy_chains(kToyChains, kToyIterations, 0.3f, 0.1f, kNoRestore, 11));
  EXPECT_FALSE(fit.joint.passed && fit.u2.passed) << fit.joint.summary() << "; " << fit.u2.summary();
}

TEST(MltStationary, WrongAcceptanceFails) {
  const ToyFit fit = toy_fit(toy_chains(kToyChains, kToyIterations, 0.3f, 0.1f, kSqrtAcceptance, 11));
  EXPECT_FALSE(fit.joint.passed) << fit.joint.summary();
}

// The small steps' normal numbers (fast native_ functions, sign from its own bit): a
// standard normal by chi-square over 40 equiprobable-width bins in [-4, 4] and the tails.
TEST(MltStationary, SmallStepsAreStandardNormal) {
  constexpr uint32_t kN = 200000;
  cl::Context& ctx = test::device_context();
  cl::Buffer out(ctx, kN * sizeof(float));
  cl::Kernel k(test::test_program("kernels/mlt_test.cl"), "mlt_gaussians");
  k.args(0, kN, out);
  k.launch(ctx, kN);
  const std::vector<float> g = out.read_vector<float>(kN);
  constexpr int kBins = 40;
  const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  std::vector<double> observed(kBins + 2, 0.0), expected(kBins + 2, 0.0);
  for (float v : g) {
    ASSERT_TRUE(std::isfinite(v));
    const int b = v < -4.0f ? 0 : v >= 4.0f ? kBins + 1 : 1 + std::min(kBins - 1, int((v + 4.0f) / 8.0f * kBins));
    observed[b] += 1.0;
  }
  expected[0] = cdf(-4.0) * kN;
  expected[kBins + 1] = (1.0 - cdf(4.0)) * kN;
  for (int b = 0; b < kBins; ++b)
    expected[1 + b] = (cdf(-4.0 + 8.0 * (b + 1) / kBins) - cdf(-4.0 + 8.0 * b / kBins)) * kN;
  const test::Chi2Result r = test::chi2_counts(observed, expected, test::Chi2Options{},
                                               [](size_t c) { return "bin " + std::to_string(c); });
  EXPECT_TRUE(r.passed) << r.report;
}

// A small step's two coordinates of one sample_2d (pss_gaussian2, a Box-Muller pair): each a
// standard normal and the two independent, by chi-square over 12 x 12 cells of equal
// probability under two independent normals (the cells of Phi(x), Phi(y)). Taking the pair's
// angle over a quarter turn (as pss_gaussian does for one number with a sign bit of its own)
// leaves both positive and fails it; so does a pair of x and x.
TEST(MltStationary, SmallStepPairsAreIndependentStandardNormals) {
  constexpr uint32_t kN = 144000;
  constexpr int kCells = 12;
  cl::Context& ctx = test::device_context();
  cl::Buffer out(ctx, 2 * kN * sizeof(float));
  cl::Kernel k(test::test_program("kernels/mlt_test.cl"), "mlt_gaussian_pairs");
  k.args(0, kN, out);
  k.launch(ctx, kN);
  const std::vector<float> g = out.read_vector<float>(2 * kN);
  const auto cell = [](float v) {
    const double p = 0.5 * std::erfc(-double(v) / std::sqrt(2.0));
    return std::min(kCells - 1, int(p * kCells));
  };
  std::vector<double> observed(kCells * kCells, 0.0);
  for (uint32_t i = 0; i < kN; ++i) {
    ASSERT_TRUE(std::isfinite(g[2 * i]) && std::isfinite(g[2 * i + 1]));
    observed[cell(g[2 * i]) * kCells + cell(g[2 * i + 1])] += 1.0;
  }
  const std::vector<double> expected(kCells * kCells, double(kN) / (kCells * kCells));
  const test::Chi2Result r = test::chi2_counts(observed, expected, test::Chi2Options{},
                                               [](size_t c) { return "cell " + std::to_string(c); });
  EXPECT_TRUE(r.passed) << r.report;
}

// A chain's pool of large steps (integrators/mlt/large_steps.cl): each of its picks is one of
// the proposals in proportion to its target, independently of the others; a proposal of
// target 0 is never picked. Drawing with the sum before the proposal is added (target / old
// sum) fails it.
TEST(MltPool, PicksAreProportionalToTheTargets) {
  const std::vector<float> t = {0.0f, 1.0f, 3.0f, 0.0f, 0.5f, 2.0f, 6.0f, 0.25f, 0.0f, 1.25f};
  constexpr uint32_t kTrials = 20000;
  const uint32_t n = uint32_t(t.size());
  cl::Context& ctx = test::device_context();
  const cl::Buffer targets = cl::Buffer::from_vector(ctx, t, CL_MEM_READ_ONLY, "targets");
  cl::Buffer sums(ctx, kTrials * sizeof(float)), picks(ctx, kTrials * MLT_PICKS * sizeof(uint32_t));
  cl::Kernel k(test::test_program("kernels/mlt_test.cl"), "mlt_pool_picks");
  k.args(0, kTrials, n, targets, sums, picks);
  k.launch(ctx, kTrials);
  double total = 0.0;
  for (float v : t) total += v;
  for (float s : sums.read_vector<float>(kTrials)) ASSERT_NEAR(s, total, 1e-6 * total);
  std::vector<double> observed(n, 0.0), expected(n, 0.0);
  for (uint32_t p : picks.read_vector<uint32_t>(kTrials * MLT_PICKS)) {
    ASSERT_LT(p, n) << "a pick is none of the pool's proposals with light";
    observed[p] += 1.0;
  }
  std::vector<double> obs, exp;
  for (uint32_t i = 0; i < n; ++i) {
    if (t[i] == 0.0f) {
      EXPECT_EQ(observed[i], 0.0) << "proposal " << i << " of target 0 was picked";
      continue;
    }
    obs.push_back(observed[i]);
    exp.push_back(double(t[i]) / total * kTrials * MLT_PICKS);
  }
  const test::Chi2Result r = test::chi2_counts(obs, exp, test::Chi2Options{},
                                               [](size_t c) { return "proposal " + std::to_string(c); });
  EXPECT_TRUE(r.passed) << r.report;
}

// ---- Host resampling. ----
TEST(MltResample, IsProportionalToTheTargets) {
  const std::vector<float> targets = {0.0f, 1.0f, 0.0f, 3.0f, 4.0f, 0.0f};
  const std::vector<uint32_t> start = Metropolis::resample(targets, 8000, 0.37);
  ASSERT_EQ(start.size(), 8000u);
  std::vector<int> count(targets.size(), 0);
  for (uint32_t s : start) ++count.at(s);
  EXPECT_EQ(count[0] + count[2] + count[5], 0) << "a black path was chosen";
  // Systematic resampling: each path gets its share to within one chain.
  EXPECT_NEAR(count[1], 1000, 1);
  EXPECT_NEAR(count[3], 3000, 1);
  EXPECT_NEAR(count[4], 4000, 1);
}

TEST(MltResample, AllBlackGivesNoStart) {
  EXPECT_TRUE(Metropolis::resample({0.0f, 0.0f}, 4, 0.5).empty());
  EXPECT_TRUE(Metropolis::resample({}, 4, 0.5).empty());
}

TEST(MltResample, ChainsPerLengthFollowB) {
  // Largest remainders of 100 * b_d / sum b: 50.0, 30.0, 15.0, 5.0.
  EXPECT_EQ(Metropolis::allocate({0.5, 0.3, 0.15, 0.05}, 100),
            (std::vector<uint32_t>{50, 30, 15, 5}));
  // 10 chains over thirds: 3.33 each, the one left over to the first largest remainder.
  EXPECT_EQ(Metropolis::allocate({1.0, 1.0, 1.0}, 10), (std::vector<uint32_t>{4, 3, 3}));
  // A length with light but a quota below one still gets a chain, from the largest share.
  EXPECT_EQ(Metropolis::allocate({1.0, 1e-6, 0.0}, 8), (std::vector<uint32_t>{7, 1, 0}));
  // Too few chains to give every length one: the larger lengths keep theirs.
  EXPECT_EQ(Metropolis::allocate({1.0, 0.5, 0.25}, 1), (std::vector<uint32_t>{1, 0, 0}));
  EXPECT_EQ(Metropolis::allocate({0.0, 0.0}, 5), (std::vector<uint32_t>{0, 0}));
  uint32_t sum = 0;
  for (uint32_t n : Metropolis::allocate({0.7, 0.2, 0.06, 0.03, 0.01}, 65536)) sum += n;
  EXPECT_EQ(sum, 65536u);
}

TEST(MltResample, TileImportanceEvensOutTheImage) {
  // A 4 x 2 film in tiles of 2: tile 0 (x 0-1) bright, tile 1 (x 2-3) a quarter as bright, as
  // two lengths' bootstrap paths (i % 2) saw them: 8 paths per length.
  std::vector<float> target;
  std::vector<uint32_t> pixel;
  for (uint32_t i = 0; i < 16; ++i) {
    const uint32_t p = (i / 2) % 8;  // every pixel once per length
    pixel.push_back(p);
    target.push_back((p % 4) < 2 ? 4.0f : 1.0f);
  }
  const std::vector<float> w = Metropolis::tile_importance(target, pixel, 2, 4, 2, 2, 1.0);
  // Per length 4 paths in each tile, summing to 16 (tile 0) and 4 (tile 1). Image mean
  // sum_d (1/8) sum I = 2 * (16 + 4) / 8 = 5; tile 0's mean 2 * 16 / 8 / (4/8) = 8, tile 1's
  // 2 (above the floor 0.3 * 5); weights 5/8 and 5/2.
  ASSERT_EQ(w.size(), 8u);
  for (uint32_t p = 0; p < 8; ++p) EXPECT_FLOAT_EQ(w[p], (p % 4) < 2 ? 5.0f / 8.0f : 5.0f / 2.0f) << p;
  // The default exponent keeps part of the luminance's pull: weights (5/8)^e and (5/2)^e, so
  // the bright tile's share of the target, 8 (5/8)^e against 2 (5/2)^e, stays above the dim
  // one's (equal at e = 1).
  const double e = Metropolis::kTileExponent;
  const std::vector<float> p = Metropolis::tile_importance(target, pixel, 2, 4, 2, 2, e);
  EXPECT_FLOAT_EQ(p[0], float(std::pow(5.0 / 8.0, e)));
  EXPECT_FLOAT_EQ(p[2], float(std::pow(5.0 / 2.0, e)));
  EXPECT_GT(8.0 * p[0], 2.0 * p[2]);
  // A tile the bootstrap saw black gets the floor: 1 / 0.3 of the image's weight.
  for (float& t : target) t = (t == 1.0f) ? 0.0f : t;
  const std::vector<float> f = Metropolis::tile_importance(target, pixel, 2, 4, 2, 2, 1.0);
  EXPECT_FLOAT_EQ(f[2], float(1.0 / 0.3));
  EXPECT_FLOAT_EQ(f[0], 0.5f);  // image 4, tile 8
}

TEST(MltResample, DefaultChainsFitTheBudget) {
  EXPECT_EQ(Metropolis::default_chains(1000, 76, size_t(256) << 20, 65536), 1000u);
  EXPECT_EQ(Metropolis::default_chains(size_t(1) << 22, 76, size_t(256) << 20, 65536), 65536u);
  EXPECT_EQ(Metropolis::default_chains(size_t(1) << 22, 76, size_t(256) << 20, 2048), 2048u);
  const uint32_t fit = Metropolis::default_chains(size_t(1) << 22, PSS_DIMS(1024), size_t(256) << 20, 65536);
  EXPECT_LE(fit * (sizeof(dev::MltChain) + PSS_DIMS(1024) * sizeof(dev::PssCoord)), size_t(256) << 20);
  EXPECT_GT(fit, 1000u);
  // The device's cap: GPUs 65536, CPU devices 1024 per compute unit (at most 65536).
  EXPECT_EQ(Metropolis::default_chain_cap(false, 132), 65536u);
  EXPECT_EQ(Metropolis::default_chain_cap(true, 2), 2048u);
  EXPECT_EQ(Metropolis::default_chain_cap(true, 0), 1024u);
  EXPECT_EQ(Metropolis::default_chain_cap(true, 256), 65536u);
}

// ---- Renders. ----
// mmlt with the tile target (the defaults), or pssmlt with the luminance target (session 8's
// integrator): the two ends, each tested on every render below.
RenderSettings mlt_settings(uint32_t size, uint64_t spp, bool multiplexed = true) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.integrator = "mlt";
  s.mlt.multiplexed = multiplexed;
  if (!multiplexed) s.mlt.importance_tile = 0;
  return s;
}

const char* mode_name(bool multiplexed) { return multiplexed ? "mmlt" : "pssmlt"; }

struct MltFurnaceCase {
  test::FurnaceCase furnace;
  bool multiplexed;
  float direct = kMltDirectAuto;  // 0: the chains sample bounces 0 and 1 too
};

class SphereFurnaceMlt : public ::testing::TestWithParam<MltFurnaceCase> {};

// Every pixel sees the same radiance, so the chains' splats must cover the film evenly: the
// image mean (b's estimate, in effect) and each 4 x 4 block against the closed form.
TEST_P(SphereFurnaceMlt, MatchesClosedForm) {
  const test::FurnaceCase c = GetParam().furnace;
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  RenderSettings s = mlt_settings(16, 64, GetParam().multiplexed);
  s.max_depth = c.max_depth;
  s.mlt.direct = GetParam().direct;
  s.mlt.bootstrap = 10000;  // b to about 0.5 %; the default 100 000 took most of the test's time
  const std::vector<Image> batches = test::render_batches(scene, s, 24, 3100);
  const test::ChannelMeans m = test::channel_means(batches);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_LT(std::fabs(m.mean[ch] - expected) / m.sigma[ch], 4.0)
        << "channel " << ch << " mean " << m.mean[ch] << " expected " << expected;
    EXPECT_LT(4.0 * m.sigma[ch], 0.03 * expected) << "too few samples for a meaningful test";
  }
  Image flat(16, 16), zero(16, 16);
  std::fill(flat.rgb.begin(), flat.rgb.end(), float(expected));
  const test::BlockTestResult blocks = test::block_means_test(batches, flat, zero, 4);
  EXPECT_EQ(blocks.failed, 0u) << blocks.summary();
  std::cout << "[ figures  ] " << mode_name(GetParam().multiplexed) << " furnace rho " << c.rho
            << " depth " << c.max_depth << ": mean "
            << m.mean[0] << " expected " << expected << " sigma " << m.sigma[0] << "; "
            << blocks.summary() << "\n";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SphereFurnaceMlt,
    ::testing::Values(MltFurnaceCase{{0.5f, 1}, true}, MltFurnaceCase{{0.8f, 8}, true},
                      MltFurnaceCase{{0.8f, 8}, true, 0.0f}, MltFurnaceCase{{0.5f, 1}, false},
                      MltFurnaceCase{{0.8f, 8}, false}, MltFurnaceCase{{0.8f, 8}, false, 0.0f}),
    [](const auto& info) {
      return std::string(mode_name(info.param.multiplexed)) +
             (info.param.direct == 0.0f ? "_chains_only_" : "_") +
             test::furnace_case_name(info.param.furnace);
    });

// ---- The direct light apart (--mlt-direct). ----
// auto's R: the share of the bootstrap's target that paths of bounces below `first` carry.
TEST(MltDirect, RatioIsTheShareOfTheShortPaths) {
  // Path i has i % 3 bounces: bounces 0 and 1 carry 1 + 2 + 1 + 2 of 12.
  EXPECT_DOUBLE_EQ(Metropolis::direct_ratio({1, 2, 3, 1, 2, 3}, 3, 2), 0.5);
  EXPECT_DOUBLE_EQ(Metropolis::direct_ratio({1, 2, 3, 1, 2, 3}, 3, 0), 0.0);
  EXPECT_DOUBLE_EQ(Metropolis::direct_ratio({0, 0, 0}, 3, 2), 0.0);
}

// At --max-depth 1 the chains have nothing left to sample (mmlt: no path length; pssmlt: its
// paths count bounces 2 on), and with R = 1 each pass takes as many direct samples as
// mutations, weighted 1: the image is the `direct` integrator's, sample for sample (the same
// indices), up to the order of the film's sums.
TEST(MltDirect, AtOneBounceItIsTheDirectIntegrator) {
  for (const bool multiplexed : {true, false}) {
    RenderSettings s = mlt_settings(16, 37, multiplexed);
    s.max_depth = 1;
    s.mlt.direct = 1.0f;
    s.seed = 11;
    const Scene scene = test::cornell_box();
    const RenderOutput mlt = Renderer(test::device_context(), scene, s).render();
    RenderSettings d = s;
    d.integrator = "direct";
    const RenderOutput direct = Renderer(test::device_context(), scene, d).render();
    const double rel = compare_images(mlt.film.mean, direct.film.mean).rel_mse;
    EXPECT_LT(rel, 1e-10) << mode_name(multiplexed);
    EXPECT_EQ(mlt.stats.metropolis.direct_samples, 37u) << mode_name(multiplexed);
    for (uint32_t n : mlt.stats.metropolis.chains_by_depth) EXPECT_EQ(n, 0u);
    std::cout << "[ figures  ] " << mode_name(multiplexed) << " at one bounce against direct: relMSE "
              << rel << "\n";
  }
}

// pssmlt's bootstrap paths leave bounces 0 and 1 out (b is the chains' part alone: in the
// furnace sum_{2 <= d <= D} rho^d Le), and its auto R comes from the direct light's first
// samples, the furnace's 1 + rho at every pixel: R = (1 + rho) / sum_{d <= D} rho^d, as mmlt's.
TEST(MltDirect, PssmltLeavesTheDirectLightToItsOwnSamples) {
  constexpr float kRho = 0.6f;
  constexpr uint32_t kDepth = 5;
  RenderSettings s = mlt_settings(32, 64, false);
  s.max_depth = kDepth;
  s.mlt.bootstrap = 100000;
  const RenderOutput out = Renderer(test::device_context(), test::furnace_scene(kRho, 1.0f), s).render();
  const MetropolisStats& m = out.stats.metropolis;
  double all = 0.0;
  for (uint32_t d = 0; d <= kDepth; ++d) all += std::pow(double(kRho), double(d));
  const double chains = all - 1.0 - kRho, direct = 1.0 + kRho, expected = direct / all;
  // b against its standard error (z < 4); R = direct / (direct + b) carries b's error,
  // direct sigma_b / (direct + b)^2, and the direct samples' own, which a furnace's pt keeps
  // near zero (each sample's NEE and emission hit add up to nearly 1 + rho): 4 sigma_R and
  // 0.1 % of R for them.
  const double sigma_b = m.b_standard_error;
  EXPECT_GT(sigma_b, 0.0);
  EXPECT_LT(std::fabs(m.b_bootstrap - chains), 4.0 * sigma_b) << "sigma_b " << sigma_b;
  const double sigma_r = direct * sigma_b / ((direct + chains) * (direct + chains));
  EXPECT_LT(std::fabs(m.direct_ratio - expected), 4.0 * sigma_r + 0.001 * expected);
  EXPECT_NEAR(double(m.direct_samples), m.direct_ratio * 64.0, 8.0);  // one rounding a pass
  std::cout << "[ figures  ] pssmlt furnace rho " << kRho << " depth " << kDepth << ": b "
            << m.b_bootstrap << " expected " << chains << " (sigma " << sigma_b << "), auto R "
            << m.direct_ratio << " expected " << expected << " (sigma from b " << sigma_r << "), "
            << m.direct_samples << " direct samples for 64 mutations per pixel\n";
}

// In the furnace a path of d bounces carries Le rho^d, so with the luminance target auto's R
// is (1 + rho) / sum_{d <= D} rho^d; the render takes about R times as many direct samples as
// mutations (round(R n) a pass).
TEST(MltDirect, AutoRatioIsTheFurnacesDirectShare) {
  constexpr float kRho = 0.6f;
  constexpr uint32_t kDepth = 5;
  RenderSettings s = mlt_settings(16, 64);
  s.max_depth = kDepth;
  s.mlt.importance_tile = 0;
  s.mlt.bootstrap = 100000;
  const RenderOutput out = Renderer(test::device_context(), test::furnace_scene(kRho, 1.0f), s).render();
  const MetropolisStats& m = out.stats.metropolis;
  double all = 0.0;
  for (uint32_t d = 0; d <= kDepth; ++d) all += std::pow(double(kRho), double(d));
  const double expected = (1.0 + kRho) / all;
  // The bootstrap's 100 000 paths a length put R's standard error near 0.1 %.
  EXPECT_NEAR(m.direct_ratio, expected, 0.01 * expected);
  EXPECT_NEAR(double(m.direct_samples), m.direct_ratio * 64.0, 8.0);  // one rounding a pass
  EXPECT_EQ(m.chains_by_depth[0], 0u);
  EXPECT_EQ(m.chains_by_depth[1], 0u);
  EXPECT_GT(m.chains_by_depth[2], 0u);
  std::cout << "[ figures  ] mmlt furnace rho " << kRho << " depth " << kDepth << ": auto R "
            << m.direct_ratio << " expected " << expected << ", " << m.direct_samples
            << " direct samples for 64 mutations per pixel\n";
}

// In the furnace every path of d bounces carries Le rho^d exactly, so each path length's
// bootstrap mean b_d, which mmlt estimates from one strategy per path (chosen uniformly,
// scaled by d + 2, MIS-weighted), must be that: a strategy with a wrong factor, or weights
// that do not sum to one over the length's strategies, moves its length's b_d. Emission,
// next-event estimation, connections and light tracing all occur: the inner sphere is seen
// from the camera and emits too.
TEST(MmltFurnace, EachPathLengthCarriesItsShare) {
  constexpr float kRho = 0.6f;
  constexpr uint32_t kDepth = 5;
  RenderSettings s = mlt_settings(16, 1);
  s.max_depth = kDepth;
  s.mlt.importance_tile = 0;  // b_d of the luminance target
  s.mlt.bootstrap = 100000;
  s.mlt.chains = 64;
  s.mlt.direct = 0.0f;  // every length's b_d: bounces 0 and 1 not rendered apart
  const RenderOutput out = Renderer(test::device_context(), test::furnace_scene(kRho, 1.0f), s).render();
  const MetropolisStats& m = out.stats.metropolis;
  ASSERT_EQ(m.b_by_depth.size(), kDepth + 1);
  ASSERT_EQ(m.b_depth_standard_error.size(), kDepth + 1);
  // |z| < 3.8: two-sided 1.4e-4 per length, 1e-3 over the six.
  const double threshold = 3.8;
  std::ostringstream fig;
  fig << "[ figures  ] mmlt furnace rho " << kRho << ", b_d / (rho^d Le) by d:";
  for (uint32_t d = 0; d <= kDepth; ++d) {
    const double expected = std::pow(double(kRho), double(d));
    const double se = m.b_depth_standard_error[d];
    EXPECT_LE(std::fabs(m.b_by_depth[d] - expected), threshold * se + 1e-6 * expected)
        << "length " << d << ": b_d " << m.b_by_depth[d] << " expected " << expected << " +- " << se;
    EXPECT_LT(threshold * se, 0.05 * expected) << "length " << d << ": too few paths to tell";
    fig << " " << m.b_by_depth[d] / expected << " (+-" << se / expected << ")";
  }
  std::cout << fig.str() << "\n";
}

constexpr uint32_t kSize = 32;

const Scene& cornell() {
  static const Scene scene = test::cornell_box();
  return scene;
}

// 48 batches, not the 16 of lt and bdpt: a pixel's value is a count of correlated chain
// splats, skewed to the right, and with 16 batches the per-pixel t-statistics came out
// heavier-tailed than Student's (9 of 3072 pixel-channels and 16 of 768 2 x 2 blocks beyond
// the threshold, nearly all below the reference); with 64 batches of the same renders, none
// and 3, with a mean z of 0.004 where a bias would have doubled them
// (docs/concepts/metropolis.md).
TEST(CrossIntegrator, MmltMatchesPtOnCornellBox) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  // 30 000 bootstrap paths per length (270 000 a batch): the default 100 000 per length took
  // 31 of the test's 45 s; b's error per batch (about 4 %) is part of the batches' spread.
  RenderSettings s = mlt_settings(kSize, 64);
  s.mlt.bootstrap = 30000;
  test::expect_matches_reference(test::render_batches(cornell(), s, 48, 900), ref, "mmlt");
}

TEST(CrossIntegrator, PssmltMatchesPtOnCornellBox) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  test::expect_matches_reference(
      test::render_batches(cornell(), mlt_settings(kSize, 64, false), 48, 900), ref, "pssmlt");
}

// pssmlt with the tile target (the command line's default), its direct light apart: the
// bootstrap's weight paths count every depth, its b paths and the chains bounces 2 on. b from
// paths of every depth would make the image too bright by the direct light's share.
TEST(CrossIntegrator, PssmltTileTargetMatchesPtOnCornellBox) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = mlt_settings(kSize, 64, false);
  s.mlt.importance_tile = kMltTile;
  s.mlt.bootstrap = 30000;
  test::expect_matches_reference(test::render_batches(cornell(), s, 48, 900), ref, "pssmlt tile");
}

// One mutation per pixel with one chain per pixel: the image is mostly the chains' start
// states, each splatted with weight b / I. Resampled in proportion to I they average to the
// image; taken as they come (uniform in primary sample space) the dim pixels, which start
// more chains than their share of I, come out too bright.
test::BlockTestResult startup_blocks(bool resample) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = mlt_settings(kSize, 1);
  s.mlt.chains = kSize * kSize;
  s.mlt.bootstrap = 20000;
  s.mlt.resample = resample;
  const std::vector<Image> batches = test::render_batches(cornell(), s, 32, 5000);
  return test::block_means_test(batches, ref.mean,
                                variance_of_mean(ref.variance, ref.samples_per_pixel), 8);
}

TEST(MltStartUp, ShortRunsMatchTheReference) {
  const test::BlockTestResult t = startup_blocks(true);
  EXPECT_EQ(t.failed, 0u) << t.summary();
  std::cout << "[ figures  ] mlt start-up, resampled: " << t.summary() << "\n";
}

TEST(MltStartUp, WithoutResamplingShortRunsAreBiased) {
  const test::BlockTestResult t = startup_blocks(false);
  EXPECT_GT(t.failed, 0u) << t.summary();
  std::cout << "[ figures  ] mlt start-up, not resampled: " << t.summary() << "\n";
}

// b is the bootstrap's mean target only for the first segment: a length's chains restart
// from their own large steps' pool when it has grown kRestartGrowth-fold, with b_d that
// pool's mean. So the image's brightness does not keep the bootstrap's error: with 1 000 paths
// per length for b (a render of 1 024 mutations per pixel proposes some 35 000 large steps
// per length), the renders' image means scatter around the reference by a fraction of what
// they do with the chains never restarted (restart = false), where b is the bootstrap's to
// the end.
struct Brightness {
  double rms = 0.0;   // of (image mean / reference mean - 1) over the runs
  double mean = 0.0;  // of the same
  double se = 0.0;    // of that mean
  uint32_t restarts = 0;
};

Brightness brightness(bool restart) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  double ref_sum = 0.0;
  for (float v : ref.mean.rgb) ref_sum += v;
  RenderSettings s = mlt_settings(kSize, 1024);
  s.mlt.bootstrap = 2000;  // the tile target's b from 1000 of them per length
  s.mlt.restart = restart;
  // The chains carry the whole image, so that all of its brightness is b's: with the direct
  // light apart (the default) only the indirect 23 % of the Cornell box's is, and b's error
  // shows a quarter as much in the image mean.
  s.mlt.direct = 0.0f;
  constexpr uint32_t kRuns = 12;
  std::vector<double> e;
  Brightness b;
  for (uint32_t r = 0; r < kRuns; ++r) {
    s.seed = 7100 + r;
    const RenderOutput out = Renderer(test::device_context(), cornell(), s).render();
    double sum = 0.0;
    for (float v : out.film.mean.rgb) sum += v;
    e.push_back(sum / ref_sum - 1.0);
    b.restarts += out.stats.metropolis.restarts;
  }
  for (double x : e) {
    b.mean += x / kRuns;
    b.rms += x * x / kRuns;
  }
  b.rms = std::sqrt(b.rms);
  double var = 0.0;
  for (double x : e) var += (x - b.mean) * (x - b.mean) / (kRuns - 1);
  b.se = std::sqrt(var / kRuns);
  return b;
}

TEST(MltRestart, BrightnessOutgrowsTheBootstrap) {
  const Brightness on = brightness(true), off = brightness(false);
  std::cout << "[ figures  ] mmlt image mean / reference - 1 over 12 runs: restarting rms "
            << on.rms << " (mean " << on.mean << " +- " << on.se << ", " << on.restarts
            << " restarts); never restarting rms " << off.rms << " (mean " << off.mean
            << " +- " << off.se << ")\n";
  EXPECT_GT(on.restarts, 0u);
  EXPECT_EQ(off.restarts, 0u);
  EXPECT_LT(on.rms, 0.5 * off.rms) << "restarts did not shrink b's error";
  // No bias either: the runs' mean error within 4 standard errors (and the reference's 0.2 %).
  EXPECT_LT(std::fabs(on.mean), 4.0 * on.se + 0.002);
}

// ---- Options. ----
using test::parse_error;

TEST(MltOptions, BadValuesAreUsageErrors) {
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-large-step", "1.5"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-large-step", "-0.1"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-sigma", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-chains", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-bootstrap", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-mode", "mmlt"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-mode", "pssmlt"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-mode", "x"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--light-samples", "2"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--sampler", "sobol"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--mlt-sigma", "0.1"}), ExitCode::Usage);  // not mlt
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "auto"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "0"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "0.25"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "-1"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "x"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "nan"}), ExitCode::Usage);
  // The ratio is parsed once, where it is checked: the number reaches the settings, auto none.
  const auto ratio = [](const char* value) {
    const char* argv[] = {"clpt", "s.gltf", "--integrator", "mlt", "--mlt-direct", value};
    return parse_options(6, argv)->mlt_direct_ratio;
  };
  EXPECT_EQ(ratio("0.25"), std::optional<float>(0.25f));
  EXPECT_EQ(ratio("0"), std::optional<float>(0.0f));
  EXPECT_FALSE(ratio("auto").has_value());
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-direct", "100"}), ExitCode::Usage);
  // Both modes render the direct light apart.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-mode", "pssmlt", "--mlt-direct", "0"}),
            ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-mode", "pssmlt", "--mlt-direct", "0.5"}),
            ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--mlt-direct", "0.5"}), ExitCode::Usage);  // not mlt
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "mlt", "--mlt-sigma", "0.05",
                         "--mlt-large-step", "1", "--mlt-chains", "7"}),
            ExitCode::Ok);
}

TEST(MltOptions, RendererChecksItsConfig) {
  RenderSettings s = mlt_settings(8, 1);
  s.mlt.sigma = 0.0f;
  try {
    Renderer r(test::device_context(), test::furnace_scene(0.5f, 1.0f), s);
    FAIL() << "sigma 0 was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
  }
  // The tile target needs two rounds of bootstrap paths; refused before any kernel runs.
  s = mlt_settings(8, 1);
  s.mlt.bootstrap = 1;
  try {
    Renderer r(test::device_context(), test::furnace_scene(0.5f, 1.0f), s);
    FAIL() << "a bootstrap of 1 with the tile target was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
  }
}

}  // namespace
}  // namespace clpt::mlt_test
