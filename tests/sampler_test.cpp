// Sampler*: the --sampler implementations (kernels/sampler/), evaluated through a test kernel
// (tests/kernels/sampler_test.cl) on a grid of (pixel, sample index, dimension).
//   SamplerRange         every value in [0, 1), finite, also at huge indices and dimensions
//   SamplerStratified    every cell of the nx x ny grid and every 1D stratum holds one sample;
//                        the strata of two samples form a uniform pair (rich permutations)
//   SamplerLhs           every stratum of every dimension holds one sample
//   SamplerSobol         power-of-two prefixes are (0,k,2)-nets; progressive
//   SamplerFallback      stratified/lhs without (or past) spp_total sample independently
//   SamplerDecorrelation χ² independence of pairs/dimensions of one pixel, pooled over pixels
//   SamplerUniformity    χ² of one sample's values across pixels
//   SamplerJitter        offsets inside strata of two samples of a pixel are independent
//   SamplerDeterminism   same inputs same bits; another seed other values; pure in the index
//   SamplerVariance      MSE of a smooth 2D integral falls well below independent sampling's
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "shared/render_types.h"
#include "support/device.h"

namespace clpt::sampler_test {
namespace {

using u32 = uint32_t;

constexpr u32 kIndependent = dev::SAMPLER_INDEPENDENT;
constexpr u32 kStratified = dev::SAMPLER_STRATIFIED;
constexpr u32 kLhs = dev::SAMPLER_LHS;
constexpr u32 kSobol = dev::SAMPLER_SOBOL;
const u32 kAllSamplers[] = {kIndependent, kStratified, kLhs, kSobol};

const char* sampler_name(u32 t) {
  switch (t) {
    case kIndependent:
      return "independent";
    case kStratified:
      return "stratified";
    case kLhs:
      return "lhs";
    case kSobol:
      return "sobol";
  }
  return "?";
}

// Dimension layout as in kernels/sampler/dimensions.h (not included: it is OpenCL C).
constexpr u32 kDimPixel = 0, kDimBounceBase = 4, kDimPerBounce = 8, kStreamStride = 0x10000;
constexpr u32 bounce_dim(u32 bounce, u32 offset) {
  return kDimBounceBase + bounce * kDimPerBounce + offset;
}

struct F2 {
  float x, y;
};
static_assert(sizeof(F2) == 8, "float2 on the device");

struct Query {
  u32 sampler = kIndependent;
  u32 spp_total = 0;
  u32 seed = 7;
  std::vector<u32> pixels{0};
  u32 first_sample = 0;
  u32 num_samples = 1;
  std::vector<u32> dims{0};
  bool two_d = false;
};

// Values of a query: at(p, i, j) is pixel pixels[p], sample first_sample + i, dims[j].
struct Values {
  std::vector<F2> v;
  size_t samples = 0, dims = 0;
  const F2& at(size_t p, size_t i, size_t j) const { return v[(p * samples + i) * dims + j]; }
};

const cl::Program& sampler_program() {
  return test::test_program("kernels/sampler_test.cl");
}

Values run(const Query& q) {
  cl::Context& ctx = test::device_context();
  dev::RenderParams params{};
  params.seed = q.seed;
  params.spp_total = q.spp_total;
  params.sampler = q.sampler;
  params.samples_per_pass = q.num_samples;
  params.sample_offset = q.first_sample;
  cl::Buffer params_buf(ctx, sizeof(params), CL_MEM_READ_ONLY, &params, "render parameters");
  cl::Buffer pixels = cl::Buffer::from_vector(ctx, q.pixels);
  cl::Buffer dims = cl::Buffer::from_vector(ctx, q.dims);
  const size_t n = q.pixels.size() * q.num_samples * q.dims.size();
  cl::Buffer out(ctx, n * sizeof(F2), CL_MEM_WRITE_ONLY, nullptr, "sampler values");
  cl::Kernel kernel(sampler_program(), "sampler_values");
  kernel.args(0, params_buf, pixels, u32(q.pixels.size()), q.first_sample, q.num_samples, dims,
              u32(q.dims.size()), u32(q.two_d ? 1 : 0), out);
  kernel.launch(ctx, n);
  Values r;
  r.v = out.read_vector<F2>(n);
  r.samples = q.num_samples;
  r.dims = q.dims.size();
  return r;
}

std::vector<u32> pixel_range(u32 first, u32 count) {
  std::vector<u32> p(count);
  std::iota(p.begin(), p.end(), first);
  return p;
}

// nx of the stratified sampler's grid: the largest divisor of n not above sqrt(n).
u32 grid_width(u32 n) {
  u32 r = 1;
  for (u32 d = 1; uint64_t(d) * d <= n; ++d)
    if (n % d == 0) r = d;
  return r;
}

// The stratum of v in n equal strata, exactly (v * n is exact in double for these n).
u32 stratum(float v, u32 n) { return u32(std::floor(double(v) * double(n))); }

// True when the values, mapped to strata, hit every one of `cells` exactly once.
bool one_per_cell(const std::vector<u32>& cell_of_sample, u32 cells) {
  std::vector<int> count(cells, 0);
  for (u32 c : cell_of_sample) {
    if (c >= cells) return false;
    ++count[c];
  }
  return std::all_of(count.begin(), count.end(), [](int c) { return c == 1; });
}

// Pearson χ² p-value for counts against equal expected counts (all expected counts here
// are far above 5, so no pooling is needed).
double chi2_uniform_p(const std::vector<double>& counts) {
  const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
  const double expected = total / double(counts.size());
  EXPECT_GE(expected, 5.0) << "too few samples per cell for a χ² test";
  double chi2 = 0.0;
  for (double c : counts) chi2 += (c - expected) * (c - expected) / expected;
  const double dof = double(counts.size() - 1);
  return boost::math::gamma_q(dof / 2.0, chi2 / 2.0);
}

// Šidák: the per-test level that keeps the family-wise level at 0.01 over m tests.
double sidak(int m) { return 1.0 - std::pow(1.0 - 0.01, 1.0 / double(m)); }

// ---------------------------------------------------------------------------------------
// Range

TEST(SamplerRange, AllValuesInUnitIntervalAndFinite) {
  const std::vector<u32> dims = {0,
                                 1,
                                 2,
                                 bounce_dim(0, 0),
                                 bounce_dim(3, 5),
                                 bounce_dim(200, 6),
                                 kStreamStride * 300 + 50,
                                 kStreamStride * 65535 + 4,
                                 0xfffffffeu};
  struct Case {
    u32 spp_total, first_sample, num_samples;
  };
  // Ordinary, non-square, prime and huge counts; indices past spp_total (fallback); spp 0;
  // indices near 2^32.
  const Case cases[] = {{64, 0, 64},
                        {12, 0, 24},
                        {7, 0, 7},
                        {0, 0, 32},
                        {1, 0, 2},
                        {100000, 99000, 32},
                        {0xffffffffu, 0xffffffe0u, 32},
                        {0, 0xffffffe0u, 32},
                        {1u << 24, (1u << 24) - 16, 16},
                        {(1u << 24) + 1, 5, 8}};
  for (u32 sampler : kAllSamplers)
    for (const Case& c : cases)
      for (bool two_d : {false, true}) {
        Query q;
        q.sampler = sampler;
        q.spp_total = c.spp_total;
        q.pixels = {0, 1, 77, 640 * 480 - 1, 0xffffffffu};
        q.first_sample = c.first_sample;
        q.num_samples = c.num_samples;
        q.dims = dims;
        q.two_d = two_d;
        const Values v = run(q);
        int bad = 0;
        for (const F2& f : v.v)
          for (float x : {f.x, f.y})
            if (!(x >= 0.0f && x < 1.0f)) ++bad;
        EXPECT_EQ(bad, 0) << sampler_name(sampler) << " spp_total " << c.spp_total << " first "
                          << c.first_sample << (two_d ? " 2D" : " 1D");
      }
}

// The conversions from hash bits to floats stay below 1 for the largest bit patterns, which
// random sampling practically never draws (the stratified conversion is tested by
// SamplerStratified.JitteredPointsStayInsideTheirStratum).
TEST(SamplerRange, ExtremeBitPatternsConvertBelowOne) {
  const std::vector<u32> bits = {0,           1,           0x7fffffffu, 0xffffff00u,
                                 0xffffff7fu, 0xffffff80u, 0xfffffffeu, 0xffffffffu};
  cl::Context& ctx = test::device_context();
  cl::Buffer in = cl::Buffer::from_vector(ctx, bits);
  cl::Buffer out(ctx, 2 * bits.size() * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "values");
  cl::Kernel kernel(sampler_program(), "unit_float_values");
  kernel.args(0, in, u32(bits.size()), out);
  kernel.launch(ctx, bits.size());
  const std::vector<float> v = out.read_vector<float>(2 * bits.size());
  for (size_t k = 0; k < v.size(); ++k)
    EXPECT_TRUE(v[k] >= 0.0f && v[k] < 1.0f)
        << (k % 2 ? "sobol_to_unit(" : "u32_to_unit_float(") << std::hex << bits[k / 2]
        << ") = " << std::hexfloat << v[k];
  EXPECT_EQ(v[2 * 7], 0x1.fffffep-1f);  // all ones: the largest float below 1
}

// ---------------------------------------------------------------------------------------
// Stratification

// Pixels, 2D pairs and 1D dimensions the stratification tests look at.
const std::vector<u32> kStratPixels = {0, 1, 2, 1000, 123457, 0xfffffffeu};
const std::vector<u32> kPairs = {kDimPixel, bounce_dim(0, 0), bounce_dim(0, 2), bounce_dim(5, 2),
                                 kStreamStride * 3 + bounce_dim(1, 0)};
const std::vector<u32> kDims1d = {bounce_dim(0, 4),
                                  bounce_dim(0, 5),
                                  bounce_dim(0, 6),
                                  bounce_dim(7, 4),
                                  kStreamStride * 2 + bounce_dim(0, 6),
                                  1};
const u32 kSeeds[] = {7, 0x12345678u};

Values run_all_samples(u32 sampler, u32 seed, u32 n, const std::vector<u32>& dims, bool two_d,
                       u32 spp_total) {
  Query q;
  q.sampler = sampler;
  q.seed = seed;
  q.spp_total = spp_total;
  q.pixels = kStratPixels;
  q.num_samples = n;
  q.dims = dims;
  q.two_d = two_d;
  return run(q);
}

TEST(SamplerStratified, EveryGridCellHoldsOneSample) {
  for (u32 seed : kSeeds)
    for (u32 n : {16u, 12u, 7u, 64u, 2u, 1u}) {
      const u32 nx = grid_width(n), ny = n / nx;
      const Values v = run_all_samples(kStratified, seed, n, kPairs, true, n);
      for (size_t p = 0; p < kStratPixels.size(); ++p)
        for (size_t j = 0; j < kPairs.size(); ++j) {
          std::vector<u32> cells;
          for (u32 i = 0; i < n; ++i) {
            const F2& f = v.at(p, i, j);
            cells.push_back(stratum(f.x, nx) + nx * stratum(f.y, ny));
          }
          EXPECT_TRUE(one_per_cell(cells, n))
              << "n " << n << " (" << nx << " x " << ny << ") seed " << seed << " pixel "
              << kStratPixels[p] << " pair " << kPairs[j];
        }
    }
}

TEST(SamplerStratified, Every1dStratumHoldsOneSample) {
  for (u32 seed : kSeeds)
    for (u32 n : {16u, 12u, 7u, 64u, 2u, 1u}) {
      const Values v = run_all_samples(kStratified, seed, n, kDims1d, false, n);
      for (size_t p = 0; p < kStratPixels.size(); ++p)
        for (size_t j = 0; j < kDims1d.size(); ++j) {
          std::vector<u32> cells;
          for (u32 i = 0; i < n; ++i) cells.push_back(stratum(v.at(p, i, j).x, n));
          EXPECT_TRUE(one_per_cell(cells, n)) << "n " << n << " seed " << seed << " pixel "
                                              << kStratPixels[p] << " dim " << kDims1d[j];
        }
    }
}

TEST(SamplerLhs, EveryStratumOfEveryDimensionHoldsOneSample) {
  for (u32 seed : kSeeds)
    for (u32 n : {7u, 16u, 100u, 1u}) {
      const Values v1 = run_all_samples(kLhs, seed, n, kDims1d, false, n);
      const Values v2 = run_all_samples(kLhs, seed, n, kPairs, true, n);
      for (size_t p = 0; p < kStratPixels.size(); ++p) {
        for (size_t j = 0; j < kDims1d.size(); ++j) {
          std::vector<u32> cells;
          for (u32 i = 0; i < n; ++i) cells.push_back(stratum(v1.at(p, i, j).x, n));
          EXPECT_TRUE(one_per_cell(cells, n)) << "n " << n << " seed " << seed << " pixel "
                                              << kStratPixels[p] << " 1D dim " << kDims1d[j];
        }
        for (size_t j = 0; j < kPairs.size(); ++j) {
          std::vector<u32> xs, ys;
          for (u32 i = 0; i < n; ++i) {
            xs.push_back(stratum(v2.at(p, i, j).x, n));
            ys.push_back(stratum(v2.at(p, i, j).y, n));
          }
          EXPECT_TRUE(one_per_cell(xs, n) && one_per_cell(ys, n))
              << "n " << n << " seed " << seed << " pixel " << kStratPixels[p] << " pair "
              << kPairs[j];
        }
      }
    }
}

// The jittered point of a stratum never rounds across the stratum's borders, also for the
// extreme jitters (0 and all ones) that random samples practically never produce.
TEST(SamplerStratified, JitteredPointsStayInsideTheirStratum) {
  std::vector<u32> strata, counts, bits;
  const u32 ns[] = {1,
                    2,
                    3,
                    7,
                    12,
                    16,
                    63,
                    64,
                    100,
                    255,
                    1000,
                    4097,
                    65535,
                    65536,
                    100003,
                    1u << 20,
                    (1u << 24) - 1,
                    1u << 24,
                    (1u << 24) + 1,
                    100000007,
                    0xffffffffu};
  const u32 jitters[] = {0, 1, 0x7fffffffu, 0x80000000u, 0xfffffeffu, 0xffffff00u, 0xffffffffu};
  for (u32 n : ns)
    for (u32 s : {0u, 1u, n / 3, n / 2, n - 2, n - 1})
      for (u32 b : jitters)
        if (s < n) {
          strata.push_back(s);
          counts.push_back(n);
          bits.push_back(b);
        }
  cl::Context& ctx = test::device_context();
  cl::Buffer sb = cl::Buffer::from_vector(ctx, strata), nb = cl::Buffer::from_vector(ctx, counts),
             bb = cl::Buffer::from_vector(ctx, bits);
  cl::Buffer out(ctx, strata.size() * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "values");
  cl::Kernel kernel(sampler_program(), "stratum_values");
  kernel.args(0, sb, nb, bb, u32(strata.size()), out);
  kernel.launch(ctx, strata.size());
  const std::vector<float> v = out.read_vector<float>(strata.size());
  for (size_t k = 0; k < v.size(); ++k) {
    EXPECT_TRUE(v[k] >= 0.0f && v[k] < 1.0f) << v[k];
    if (counts[k] <= (1u << 24)) {
      EXPECT_EQ(stratum(v[k], counts[k]), strata[k])
          << "n " << counts[k] << " stratum " << strata[k] << " jitter bits " << std::hex << bits[k]
          << ": value " << std::hexfloat << v[k];
    } else {
      // More strata than a float resolves: within float rounding of the stratum.
      const double lo = double(strata[k]) / counts[k], width = 1.0 / counts[k];
      EXPECT_TRUE(v[k] >= lo - 0x1p-21 && v[k] <= lo + width + 0x1p-21)
          << "n " << counts[k] << " stratum " << strata[k] << " jitter bits " << std::hex << bits[k]
          << ": value " << std::hexfloat << v[k];
    }
  }
}

// The hash-based permutations are rich: across pixels, the strata (cells) taken by two
// samples a != b of one pixel are a uniformly random ordered pair of distinct strata, and
// never the same stratum. (A family like "rotate by a random offset" keeps every
// stratification and decorrelation test above green but fails this one.)
TEST(SamplerStratified, TwoSamplesTakeAUniformPairOfStrata) {
  constexpr u32 kPixels = 65536;
  struct Case {
    u32 sampler, n;
    bool two_d;
  };
  const Case cases[] = {
      {kStratified, 16, true}, {kStratified, 7, false}, {kLhs, 16, false}, {kLhs, 7, false}};
  const std::pair<u32, u32> samples[] = {{0, 1}, {2, 6}};
  const double alpha = sidak(int(std::size(cases) * std::size(samples)));
  double min_p = 1.0;
  for (const Case& c : cases) {
    Query q;
    q.sampler = c.sampler;
    q.spp_total = c.n;
    q.pixels = pixel_range(0, kPixels);
    q.num_samples = c.n;
    q.dims = {bounce_dim(0, 2)};
    q.two_d = c.two_d;
    const Values v = run(q);
    const u32 nx = c.two_d ? grid_width(c.n) : c.n, ny = c.n / nx;
    auto cell = [&](size_t p, size_t i) {
      const F2& f = v.at(p, i, 0);
      return c.two_d ? stratum(f.x, nx) + nx * stratum(f.y, ny) : stratum(f.x, c.n);
    };
    for (const auto& [a, b] : samples) {
      std::vector<double> counts;
      std::vector<double> joint(c.n * c.n, 0.0);
      for (size_t p = 0; p < kPixels; ++p) joint[cell(p, a) * c.n + cell(p, b)] += 1;
      double same = 0;
      for (u32 x = 0; x < c.n; ++x)
        for (u32 y = 0; y < c.n; ++y) (x == y ? same : counts.emplace_back()) += joint[x * c.n + y];
      EXPECT_EQ(same, 0.0) << sampler_name(c.sampler) << " n " << c.n;
      const double pv = chi2_uniform_p(counts);
      min_p = std::min(min_p, pv);
      EXPECT_GT(pv, alpha) << sampler_name(c.sampler) << " n " << c.n << ": samples " << a
                           << " and " << b;
    }
  }
  std::printf("TwoSamplesTakeAUniformPairOfStrata: smallest p %.3g (level %.2g each)\n", min_p,
              alpha);
}

// Every aligned block of 2^k samples (k = 2..8), the prefix included, is a (0,k,2)-net:
// each elementary interval 2^-a x 2^-(k-a) holds exactly one point; in 1D each of the 2^k
// strata holds one.
TEST(SamplerSobol, PowerOfTwoBlocksAreNets) {
  constexpr u32 kMax = 256;
  for (u32 seed : kSeeds)
    for (u32 spp_total : {0u, kMax}) {  // progressive: the count does not matter
      const Values v2 = run_all_samples(kSobol, seed, kMax, kPairs, true, spp_total);
      const Values v1 = run_all_samples(kSobol, seed, kMax, kDims1d, false, spp_total);
      for (u32 k = 2; k <= 8; ++k) {
        const u32 n = 1u << k;
        for (u32 block = 0; block < kMax / n; ++block)
          for (size_t p = 0; p < kStratPixels.size(); ++p) {
            for (size_t j = 0; j < kPairs.size(); ++j)
              for (u32 a = 0; a <= k; ++a) {
                const u32 nx = 1u << a, ny = n >> a;
                std::vector<u32> cells;
                for (u32 i = block * n; i < (block + 1) * n; ++i) {
                  const F2& f = v2.at(p, i, j);
                  cells.push_back(stratum(f.x, nx) + nx * stratum(f.y, ny));
                }
                EXPECT_TRUE(one_per_cell(cells, n))
                    << "2^" << k << " points, block " << block << ", intervals " << nx << " x "
                    << ny << ", seed " << seed << ", pixel " << kStratPixels[p] << ", pair "
                    << kPairs[j];
              }
            for (size_t j = 0; j < kDims1d.size(); ++j) {
              std::vector<u32> cells;
              for (u32 i = block * n; i < (block + 1) * n; ++i)
                cells.push_back(stratum(v1.at(p, i, j).x, n));
              EXPECT_TRUE(one_per_cell(cells, n))
                  << "2^" << k << " points, block " << block << ", seed " << seed << ", pixel "
                  << kStratPixels[p] << ", 1D dim " << kDims1d[j];
            }
          }
      }
    }
}

// Progressive: the values do not depend on the announced sample count.
TEST(SamplerSobol, IndependentOfSppTotal) {
  Query q;
  q.sampler = kSobol;
  q.pixels = kStratPixels;
  q.num_samples = 40;
  q.dims = kPairs;
  q.two_d = true;
  q.spp_total = 0;
  const Values a = run(q);
  for (u32 spp_total : {1u, 16u, 40u, 1000u}) {
    q.spp_total = spp_total;
    const Values b = run(q);
    EXPECT_EQ(0, std::memcmp(a.v.data(), b.v.data(), a.v.size() * sizeof(F2)))
        << "spp_total " << spp_total;
  }
}

// ---------------------------------------------------------------------------------------
// Fallback: stratified and lhs need the sample count; without it, or for sample indices
// past it, they sample independently (bit for bit the independent sampler).

TEST(SamplerFallback, WithoutOrPastSppTotalSampleIndependently) {
  for (u32 sampler : {kStratified, kLhs})
    for (bool two_d : {false, true}) {
      struct Case {
        u32 spp_total, first, count;
        bool independent;
      };
      for (const Case& c : {Case{0, 0, 32, true}, Case{8, 8, 32, true}, Case{8, 0, 8, false},
                            Case{1, 1, 4, true}}) {
        Query q;
        q.pixels = kStratPixels;
        q.spp_total = c.spp_total;
        q.first_sample = c.first;
        q.num_samples = c.count;
        q.dims = two_d ? kPairs : kDims1d;
        q.two_d = two_d;
        q.sampler = kIndependent;
        const Values ind = run(q);
        q.sampler = sampler;
        const Values s = run(q);
        const bool same = std::memcmp(ind.v.data(), s.v.data(), s.v.size() * sizeof(F2)) == 0;
        EXPECT_EQ(same, c.independent)
            << sampler_name(sampler) << (two_d ? " 2D" : " 1D") << " spp_total " << c.spp_total
            << " samples " << c.first << ".." << c.first + c.count;
      }
    }
}

// ---------------------------------------------------------------------------------------
// Decorrelation and uniformity (χ², Šidák-corrected at a family-wise level of 0.01)

constexpr u32 kChiPixels = 4096;  // pixels pooled
constexpr u32 kChiSpp = 16;       // samples per pixel: 65536 points per histogram
constexpr u32 kBins = 8;          // 8 x 8 cells: 1024 expected per cell

// 2D pairs and 1D dimensions of one path whose values should be independent.
const std::vector<u32> kChiPairs = {kDimPixel, bounce_dim(0, 0), bounce_dim(0, 2), bounce_dim(1, 2),
                                    kStreamStride + bounce_dim(0, 0)};
const std::vector<u32> kChiDims1d = {bounce_dim(0, 4), bounce_dim(0, 6)};

// One coordinate of one query: pair j's x or y, or 1D dimension j.
struct Coord {
  bool two_d;
  size_t j;
  bool y;
  std::string name() const {
    const u32 d = two_d ? kChiPairs[j] : kChiDims1d[j];
    return (two_d ? "pair " : "1D ") + std::to_string(d) + (two_d ? (y ? ".y" : ".x") : "");
  }
};

TEST(SamplerDecorrelation, DimensionsOfOnePixelAreIndependent) {
  // Pairs of coordinates to test: the two of one pair, the same coordinate of two pairs
  // (also of two bounces and of two streams), a pair and a 1D dimension, two 1D dimensions.
  const std::pair<Coord, Coord> tests[] = {
      {{true, 0, false}, {true, 0, true}},   {{true, 0, false}, {true, 2, false}},
      {{true, 1, true}, {true, 2, true}},    {{true, 2, false}, {true, 3, false}},
      {{true, 1, false}, {true, 4, false}},  {{true, 2, true}, {false, 1, false}},
      {{false, 0, false}, {false, 1, false}}};
  const int num_tests = int(std::size(kAllSamplers) * std::size(tests));
  const double alpha = sidak(num_tests);
  double min_p = 1.0;
  for (u32 sampler : kAllSamplers) {
    Query q;
    q.sampler = sampler;
    q.spp_total = kChiSpp;
    q.pixels = pixel_range(0, kChiPixels);
    q.num_samples = kChiSpp;
    q.dims = kChiPairs;
    q.two_d = true;
    const Values v2 = run(q);
    q.dims = kChiDims1d;
    q.two_d = false;
    const Values v1 = run(q);
    auto value = [&](const Coord& c, size_t p, size_t i) {
      const F2& f = c.two_d ? v2.at(p, i, c.j) : v1.at(p, i, c.j);
      return c.y ? f.y : f.x;
    };
    for (const auto& [a, b] : tests) {
      std::vector<double> counts(kBins * kBins, 0.0);
      for (size_t p = 0; p < kChiPixels; ++p)
        for (size_t i = 0; i < kChiSpp; ++i)
          counts[stratum(value(a, p, i), kBins) * kBins + stratum(value(b, p, i), kBins)] += 1;
      const double pv = chi2_uniform_p(counts);
      min_p = std::min(min_p, pv);
      EXPECT_GT(pv, alpha) << sampler_name(sampler) << ": " << a.name() << " vs " << b.name();
    }
  }
  std::printf("SamplerDecorrelation: %d χ² tests, smallest p %.3g (level %.2g each)\n", num_tests,
              min_p, alpha);
}

// Across pixels, one sample (a fixed index) is uniform: 1D χ² of x, of y and of a 1D
// dimension over 64 bins, 2D χ² over 8 x 8 cells.
TEST(SamplerUniformity, OneSampleIsUniformAcrossPixels) {
  constexpr u32 kPixels = 65536;
  const u32 indices[] = {0, 11};
  const double alpha = sidak(int(std::size(kAllSamplers) * std::size(indices) * 4));
  double min_p = 1.0;
  for (u32 sampler : kAllSamplers)
    for (u32 index : indices) {
      Query q;
      q.sampler = sampler;
      q.spp_total = kChiSpp;
      q.pixels = pixel_range(0, kPixels);
      q.first_sample = index;
      q.num_samples = 1;
      q.dims = {bounce_dim(0, 2)};
      q.two_d = true;
      const Values v2 = run(q);
      q.dims = {bounce_dim(0, 6)};
      q.two_d = false;
      const Values v1 = run(q);
      std::vector<double> hx(64, 0.0), hy(64, 0.0), h1(64, 0.0), hxy(64, 0.0);
      for (size_t p = 0; p < kPixels; ++p) {
        const F2& f = v2.at(p, 0, 0);
        hx[stratum(f.x, 64)] += 1;
        hy[stratum(f.y, 64)] += 1;
        hxy[stratum(f.x, 8) * 8 + stratum(f.y, 8)] += 1;
        h1[stratum(v1.at(p, 0, 0).x, 64)] += 1;
      }
      const std::string what =
          std::string(sampler_name(sampler)) + ", sample " + std::to_string(index) + ": ";
      const double p[4] = {chi2_uniform_p(hx), chi2_uniform_p(hy), chi2_uniform_p(hxy),
                           chi2_uniform_p(h1)};
      EXPECT_GT(p[0], alpha) << what << "pair x";
      EXPECT_GT(p[1], alpha) << what << "pair y";
      EXPECT_GT(p[2], alpha) << what << "pair (x, y)";
      EXPECT_GT(p[3], alpha) << what << "1D";
      min_p = std::min({min_p, p[0], p[1], p[2], p[3]});
    }
  std::printf("SamplerUniformity: smallest p %.3g (level %.2g each)\n", min_p, alpha);
}

// Inside their strata, the points of one pixel are jittered independently: the offsets
// (n v mod 1) of two samples of a pixel, pooled over pixels, are jointly uniform. Catches
// a shared or constant jitter and, for Sobol, a missing value scramble (a shuffled but
// unscrambled net puts every point at the same offset inside its stratum).
TEST(SamplerJitter, OffsetsInsideStrataAreIndependent) {
  constexpr u32 kPixels = 16384, kN = 16;
  const u32 samplers[] = {kStratified, kLhs, kSobol};
  const std::pair<u32, u32> samples[] = {{0, 1}, {3, 12}};
  const double alpha = sidak(int(std::size(samplers) * std::size(samples) * 3));
  double min_p = 1.0;
  for (u32 sampler : samplers) {
    Query q;
    q.sampler = sampler;
    q.spp_total = kN;
    q.pixels = pixel_range(0, kPixels);
    q.num_samples = kN;
    q.dims = {bounce_dim(0, 2)};
    q.two_d = true;
    const Values v2 = run(q);
    q.dims = {bounce_dim(0, 6)};
    q.two_d = false;
    const Values v1 = run(q);
    // Strata per coordinate: pair x, pair y, 1D.
    const u32 nx = sampler == kStratified ? grid_width(kN) : kN;
    const u32 strata[3] = {nx, sampler == kStratified ? kN / nx : kN, kN};
    for (const auto& [a, b] : samples)
      for (int c = 0; c < 3; ++c) {
        auto offset = [&](size_t p, size_t i) {
          const double x = c == 0 ? v2.at(p, i, 0).x : c == 1 ? v2.at(p, i, 0).y : v1.at(p, i, 0).x;
          const double t = x * strata[c];
          return std::min(kBins - 1, u32((t - std::floor(t)) * kBins));
        };
        std::vector<double> counts(kBins * kBins, 0.0);
        for (size_t p = 0; p < kPixels; ++p) counts[offset(p, a) * kBins + offset(p, b)] += 1;
        const double pv = chi2_uniform_p(counts);
        min_p = std::min(min_p, pv);
        EXPECT_GT(pv, alpha) << sampler_name(sampler)
                             << (c == 0   ? " pair x"
                                 : c == 1 ? " pair y"
                                          : " 1D")
                             << ", samples " << a << " and " << b;
      }
  }
  std::printf("SamplerJitter: smallest p %.3g (level %.2g each)\n", min_p, alpha);
}

// ---------------------------------------------------------------------------------------
// Determinism

TEST(SamplerDeterminism, PureFunctionOfSeedPixelIndexDimension) {
  for (u32 sampler : kAllSamplers)
    for (bool two_d : {false, true}) {
      Query q;
      q.sampler = sampler;
      q.spp_total = 16;
      q.pixels = pixel_range(100, 64);
      q.num_samples = 16;
      q.dims = two_d ? kPairs : kDims1d;
      q.two_d = two_d;
      const Values a = run(q), b = run(q);
      const std::string what = std::string(sampler_name(sampler)) + (two_d ? " 2D" : " 1D");
      EXPECT_EQ(0, std::memcmp(a.v.data(), b.v.data(), a.v.size() * sizeof(F2))) << what;

      // A later pass (samples 5..11 alone, other pixels around) gives the same values.
      Query part = q;
      part.pixels = {q.pixels[3], q.pixels[40]};
      part.first_sample = 5;
      part.num_samples = 7;
      const Values c = run(part);
      int mismatches = 0;
      for (size_t pi = 0; pi < 2; ++pi)
        for (size_t i = 0; i < 7; ++i)
          for (size_t j = 0; j < q.dims.size(); ++j) {
            const F2 &x = c.at(pi, i, j), &y = a.at(pi == 0 ? 3 : 40, 5 + i, j);
            if (std::memcmp(&x, &y, sizeof(F2)) != 0) ++mismatches;
          }
      EXPECT_EQ(mismatches, 0) << what << ": a pass of samples 5..11 differs";

      // Another seed changes (practically) every value.
      q.seed = 8;
      const Values d = run(q);
      size_t same = 0, total = 0;
      for (size_t k = 0; k < a.v.size(); ++k) {
        same += a.v[k].x == d.v[k].x;
        ++total;
        if (two_d) {
          same += a.v[k].y == d.v[k].y;
          ++total;
        }
      }
      EXPECT_LT(double(same), 0.01 * double(total)) << what << ": another seed";
    }
}

// ---------------------------------------------------------------------------------------
// Variance reduction
//
// Per pixel, estimate a smooth integral over [0,1)^2 with N = 64 samples of one dimension
// pair; the mean squared error over many pixels estimates the estimator's variance.
// Theory for jittered stratification with an n x n grid, N = n^2, for smooth f:
// Var ≈ E|∇f|² / (12 n² N) against Var f / N for independent sampling, a ratio of
// 12 n² Var f / E|∇f|² ≈ 25 for f below (n = 8). Owen-scrambled (0,2)-nets have
// O(N^-3 log N) variance for smooth f, at least as good at N = 64. The Latin hypercube
// removes only the additive part of the variance (Owen 1997), so it is tested on the
// additive g, where theory predicts a ratio of 12 N² Var g / E|∇g|² ≈ 3600; on the
// non-additive f it must not be worse than N/(N-1) times independent sampling.
// The assertions (ratio ≥ 4; lhs on f ≤ 1.25x) are far from the measured ratios (reported
// on stdout); with 2048 pixels each MSE is known to a few percent.

double f_smooth(double x, double y) { return x * y + std::sin(3 * x) * std::cos(2 * y); }
const double kIntegralF = 0.25 + (1 - std::cos(3.0)) / 3.0 * std::sin(2.0) / 2.0;
double g_additive(double x, double y) { return std::exp(x) + y * y; }
const double kIntegralG = std::exp(1.0) - 1.0 + 1.0 / 3.0;

struct ErrorStats {
  double mse = 0, z = 0;
};

TEST(SamplerVariance, SmoothIntegrandMseBelowIndependent) {
  constexpr u32 kPixels = 2048, kN = 64;
  const std::vector<u32> pairs = {kDimPixel, bounce_dim(2, 2)};
  // [sampler][pair][integrand]
  ErrorStats stats[4][2][2];
  for (u32 sampler : kAllSamplers) {
    Query q;
    q.sampler = sampler;
    q.spp_total = kN;
    q.pixels = pixel_range(5000, kPixels);
    q.num_samples = kN;
    q.dims = pairs;
    q.two_d = true;
    const Values v = run(q);
    for (size_t j = 0; j < pairs.size(); ++j)
      for (int which = 0; which < 2; ++which) {
        double sum = 0, sum_sq = 0;
        for (size_t p = 0; p < kPixels; ++p) {
          double est = 0;
          for (size_t i = 0; i < kN; ++i) {
            const F2& f = v.at(p, i, j);
            est += which == 0 ? f_smooth(f.x, f.y) : g_additive(f.x, f.y);
          }
          const double err = est / kN - (which == 0 ? kIntegralF : kIntegralG);
          sum += err;
          sum_sq += err * err;
        }
        ErrorStats& s = stats[sampler][j][which];
        s.mse = sum_sq / kPixels;
        const double mean = sum / kPixels;
        const double sd = std::sqrt((sum_sq - kPixels * mean * mean) / (kPixels - 1));
        s.z = sd > 0 ? mean / (sd / std::sqrt(double(kPixels))) : HUGE_VAL;
      }
  }
  for (size_t j = 0; j < pairs.size(); ++j)
    for (int which = 0; which < 2; ++which) {
      const double mse_ind = stats[kIndependent][j][which].mse;
      for (u32 sampler : kAllSamplers) {
        const ErrorStats& s = stats[sampler][j][which];
        std::printf(
            "SamplerVariance: pair %u, %s: %-11s MSE %.3e  independent/this %8.1f  z %+.2f\n",
            pairs[j], which == 0 ? "f = xy + sin 3x cos 2y" : "g = e^x + y^2",
            sampler_name(sampler), s.mse, mse_ind / s.mse, s.z);
        // Unbiased: the mean error over pixels is consistent with zero (|z| < 4).
        EXPECT_LT(std::fabs(s.z), 4.0) << sampler_name(sampler) << " pair " << pairs[j]
                                       << (which == 0 ? " f" : " g") << ": biased";
      }
      const char* what = which == 0 ? " f" : " g";
      if (which == 0) {
        EXPECT_GE(mse_ind / stats[kStratified][j][which].mse, 4.0)
            << "stratified pair " << pairs[j] << what;
        EXPECT_GE(mse_ind / stats[kSobol][j][which].mse, 4.0) << "sobol pair " << pairs[j] << what;
        EXPECT_LE(stats[kLhs][j][which].mse, 1.25 * mse_ind) << "lhs pair " << pairs[j] << what;
      } else {
        EXPECT_GE(mse_ind / stats[kLhs][j][which].mse, 4.0) << "lhs pair " << pairs[j] << what;
        EXPECT_GE(mse_ind / stats[kStratified][j][which].mse, 4.0)
            << "stratified pair " << pairs[j] << what;
        EXPECT_GE(mse_ind / stats[kSobol][j][which].mse, 4.0) << "sobol pair " << pairs[j] << what;
      }
    }
}

}  // namespace
}  // namespace clpt::sampler_test
