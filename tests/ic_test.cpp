// The irradiance cache (--integrator ic) on the PoCL device:
//   IcLookup         the kernel's lookup (grid, Ward's weights, the in-front test, depth,
//                    gradient extrapolation) equals a host brute-force loop over all records,
//                    for random records and query points;
//   IcFurnace        in the furnace every record holds the same irradiance, so the image is
//                    the closed form (t-test over independent caches);
//   IcConsistency    on the Cornell box, relMSE against the 8 192-spp pt reference falls as
//                    --ic-error falls from 0.4 to 0.2 and 0.1 with the rays per record rising
//                    (256, 1024, 4096) to the pixel noise of 1 024 spp; the image mean is
//                    within 2 % at a 0.2; gradients lower the error; on a plane with a long
//                    gradient of indirect light they halve it;
//                    the glossy-and-glass box near its pt reference (mean 2 %, blocks 10 %);
//   IcOptions        usage errors;
//   IcCli            --stats' ic object, --ic-show-records' marks (a pixel per record), and two
//                    runs with one seed giving the same image (the cache is deterministic,
//                    which a resumed render relies on).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "integrators/ic_grid.h"
#include "io/image_io.h"
#include "integrators/irradiance_cache.h"
#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/parse_options.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/render.h"
#include "support/run.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt::ic_test {
namespace {

glm::vec3 vec(const float* v) { return glm::vec3(v[0], v[1], v[2]); }

// ---------------------------------------------------------------------------------------
// IcLookup

struct HostEstimate {
  glm::dvec3 e{0.0};
  double weight = 0.0;
  uint32_t records = 0;
  bool borderline = false;  // some record's error or in-front test within rounding of its bound
};

// lookup.cl's rule, written out again in double over every record.
HostEstimate brute_force(const std::vector<dev::IcRecord>& records, const dev::IcParams& ic,
                         glm::dvec3 x, glm::dvec3 n, uint32_t depth) {
  HostEstimate h;
  for (const dev::IcRecord& r : records) {
    if (r.depth != depth) continue;
    const glm::dvec3 xi = vec(r.p), ni = vec(r.n), d = x - xi;
    const double cos_n = glm::dot(n, ni);
    if (!(cos_n > 0.0)) continue;
    const double eps = glm::length(d) / r.r + std::sqrt(std::max(0.0, 1.0 - cos_n));
    const double front = glm::dot(d, 0.5 * (n + ni)) + 1e-3 * r.r;
    if (std::fabs(eps - ic.error) < 1e-4 || std::fabs(front) < 1e-4 * r.r) h.borderline = true;
    if (!(eps < ic.error) || front < 0.0) continue;
    const double w = 1.0 / std::max(eps, 1e-6);
    glm::dvec3 e = vec(r.e);
    if (ic.gradients) {
      const glm::dvec3 axis = glm::cross(ni, n);
      // The translational gradient's cap: luminance change at most E's over R.
      const glm::dvec3 g_lum = 0.2126 * glm::dvec3(vec(r.trans)) +
                               0.7152 * glm::dvec3(vec(r.trans + 3)) +
                               0.0722 * glm::dvec3(vec(r.trans + 6));
      const double e_lum = 0.2126 * r.e[0] + 0.7152 * r.e[1] + 0.0722 * r.e[2];
      const double g_len = glm::length(g_lum) * r.r;
      const double cap = g_len > e_lum ? e_lum / g_len : 1.0;
      for (int c = 0; c < 3; ++c)
        e[c] += glm::dot(axis, glm::dvec3(vec(r.rot + 3 * c))) +
                cap * glm::dot(d, glm::dvec3(vec(r.trans + 3 * c)));
      e = glm::max(e, glm::dvec3(0.0));
    }
    h.e += w * e;
    h.weight += w;
    ++h.records;
  }
  if (h.weight > 0.0) h.e /= h.weight;
  return h;
}

// Records on three planes and in the open, with radii over two orders of magnitude (several
// grid levels), two depths, and random irradiance and gradients.
std::vector<dev::IcRecord> random_records(size_t count, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<dev::IcRecord> records(count);
  for (size_t i = 0; i < count; ++i) {
    dev::IcRecord& r = records[i];
    glm::vec3 p(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1), n;
    switch (i % 4) {
      case 0: p.z = 0.0f; n = glm::vec3(0, 0, 1); break;
      case 1: p.x = 0.5f; n = glm::vec3(-1, 0, 0); break;
      case 2: p.y = -0.25f; n = glm::vec3(0, 1, 0); break;
      default: n = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
    }
    for (int a = 0; a < 3; ++a) {
      r.p[a] = p[a];
      r.n[a] = n[a];
      r.e[a] = u(rng);
    }
    r.r = 0.02f * std::pow(100.0f, u(rng));  // 0.02 to 2
    r.depth = i % 7 == 0 ? 1u : 0u;
    r.pixel = uint32_t(i);
    for (int k = 0; k < 9; ++k) {
      r.rot[k] = u(rng) - 0.5f;
      r.trans[k] = 2.0f * (u(rng) - 0.5f);
    }
  }
  return records;
}

TEST(IcLookup, KernelMatchesBruteForce) {
  cl::Context& ctx = test::device_context();
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::vector<dev::IcRecord> records = random_records(3000, rng);
  for (const bool gradients : {false, true}) {
    dev::IcParams ic{};
    ic.error = 0.3f;
    ic.gradients = gradients ? 1u : 0u;
    const IcGrid grid = build_ic_grid(records, ic.error);
    ic.level_mask = grid.level_mask;
    ic.bucket_mask = grid.bucket_mask;
    ic.inv_cell = grid.inv_cell;
    ic.record_count = uint32_t(records.size());
    EXPECT_GT(__builtin_popcount(grid.level_mask), 3) << "radii should span several levels";
    // Queries near records (on their plane or off it, normals turned a little) and anywhere.
    const uint32_t count = 4000;
    std::vector<float> queries(8 * count);
    std::vector<uint32_t> depths(count);
    for (uint32_t i = 0; i < count; ++i) {
      const dev::IcRecord& r = records[rng() % records.size()];
      glm::vec3 x = vec(r.p), n = vec(r.n);
      const float reach = ic.error * r.r;
      x += reach * 1.2f * glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 2.0f;
      if (i % 3 == 0) x += reach * 0.2f * (u(rng) - 0.5f) * n;  // a step off the surface
      n = glm::normalize(n + 0.1f * glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
      if (i % 10 == 0) x = glm::vec3(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1);
      depths[i] = i % 5 == 0 ? 1u : 0u;
      uint32_t depth_bits = depths[i];
      float w;
      std::memcpy(&w, &depth_bits, sizeof(w));
      const float q[8] = {x.x, x.y, x.z, w, n.x, n.y, n.z, 0.0f};
      std::copy(q, q + 8, queries.begin() + 8 * i);
    }
    cl::Buffer ic_buf(ctx, sizeof(ic), CL_MEM_READ_ONLY, &ic);
    cl::Buffer rec_buf = cl::Buffer::from_vector(ctx, records);
    cl::Buffer starts = cl::Buffer::from_vector(ctx, grid.starts);
    cl::Buffer entries = cl::Buffer::from_vector(ctx, grid.entries);
    cl::Buffer q_buf = cl::Buffer::from_vector(ctx, queries);
    cl::Buffer out(ctx, count * 4 * sizeof(float)), used(ctx, count * sizeof(uint32_t));
    cl::Kernel k(test::test_program("kernels/ic_test.cl"), "ic_lookup_points");
    k.args(0, ic_buf, rec_buf, starts, entries, q_buf, count, out, used);
    k.launch(ctx, count);
    const std::vector<float> est = out.read_vector<float>(4 * count);
    const std::vector<uint32_t> n_used = used.read_vector<uint32_t>(count);
    size_t compared = 0, covered = 0, bad = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const glm::dvec3 x(queries[8 * i], queries[8 * i + 1], queries[8 * i + 2]);
      const glm::dvec3 n(queries[8 * i + 4], queries[8 * i + 5], queries[8 * i + 6]);
      const HostEstimate h = brute_force(records, ic, x, n, depths[i]);
      if (h.borderline) continue;
      ++compared;
      if (h.records) ++covered;
      const double w = est[4 * i + 3];
      bool ok = n_used[i] == h.records && std::fabs(w - h.weight) <= 1e-3 * h.weight + 1e-6;
      for (int c = 0; c < 3 && ok && h.records; ++c)
        ok = std::fabs(est[4 * i + c] - h.e[c]) <= 1e-3 * (std::fabs(h.e[c]) + 1.0);
      if (!ok && bad++ < 5)
        ADD_FAILURE() << "query " << i << ": kernel " << n_used[i] << " records, weight " << w
                      << ", e " << est[4 * i] << "; brute force " << h.records << ", "
                      << h.weight << ", " << h.e.x;
    }
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(compared, count * 3 / 4);
    EXPECT_GT(covered, compared / 3) << "too few queries find records to test much";
    std::cout << "[ figures  ] ic lookup (gradients " << gradients << "): " << compared
              << " queries compared, " << covered << " covered\n";
  }
}

// The record's sums on a known radiance field, L(w) = 1 + w . g with every ray at distance
// 1e6 (a field at infinity): E = pi + (2 pi / 3) g.n, R = 1e6, and for a rotation of the normal by d
// towards tangent u, dE = (2 pi / 3) (g . u) d, i.e. grad_rot = (2 pi / 3) n x g_t (the
// lookup's dE = grad_rot . (n_i x n)); a field at infinity does not change with x:
// grad_trans = 0 (at distance 1 it would: the radiance is then painted on a unit hemisphere).
// A second batch of rays is averaged in (the refinement under --time).
// The record-sum kernel tests' cache: 1 024 rays' strata, no spacing clamp; and a record at
// the origin with normal n, footprint 1 (its R bounds then [0, 2e9]).
dev::IcParams record_sum_params() {
  dev::IcParams ic{};
  ic.error = 0.5f;
  ic.min_spacing = 0.0f;
  ic.max_spacing = 1e9f;
  IrradianceCache::strata(1024, &ic.rays_theta, &ic.rays_phi);
  return ic;
}
dev::IcRecord record_at_origin(glm::vec3 n) {
  dev::IcRecord rec{};
  for (int a = 0; a < 3; ++a) rec.n[a] = n[a];
  rec.r = 1.0f;
  return rec;
}

TEST(IcLookup, RecordSumsOnALinearField) {
  cl::Context& ctx = test::device_context();
  const dev::IcParams ic = record_sum_params();
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)), g(0.4f, 0.2f, -0.3f);
  dev::IcRecord rec = record_at_origin(n);
  cl::Buffer ic_buf(ctx, sizeof(ic), CL_MEM_READ_ONLY, &ic);
  cl::Buffer rec_buf(ctx, sizeof(rec), CL_MEM_READ_WRITE, &rec);
  cl::Buffer rays(ctx, size_t(ic.rays_theta) * ic.rays_phi * 16);
  cl::Kernel k(test::test_program("kernels/ic_test.cl"), "ic_finish_linear");
  k.args(0, ic_buf, rec_buf, rays, g.x, g.y, g.z);
  k.launch(ctx, 1);
  rec_buf.read(&rec, sizeof(rec));
  const double pi = 3.14159265358979;
  const double e = pi + 2.0 * pi / 3.0 * glm::dot(g, n);
  const glm::vec3 g_t = g - glm::dot(g, n) * n;
  const glm::vec3 rot = float(2.0 * pi / 3.0) * glm::cross(n, g_t);
  EXPECT_NEAR(rec.r, 1e6, 1e6 * 1e-4);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(rec.e[c], e, 2e-3 * e) << "channel " << c;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(rec.rot[3 * c + a], rot[a], 0.02 * glm::length(rot)) << "channel " << c << " axis " << a;
      EXPECT_NEAR(rec.trans[3 * c + a], 0.0, 1e-5) << "channel " << c << " axis " << a;
    }
  }
  // grad_rot is tangent to the record's normal.
  EXPECT_NEAR(glm::dot(vec(rec.rot), n), 0.0, 1e-4);
  // A second batch of as many rays on the field 1 - w . g: the means of the two batches,
  // E = pi and grad_rot = 0, over twice the rays.
  const uint32_t per = ic.rays_theta * ic.rays_phi;
  EXPECT_EQ(rec.rays, per);
  k.args(0, ic_buf, rec_buf, rays, -g.x, -g.y, -g.z);
  k.launch(ctx, 1);
  rec_buf.read(&rec, sizeof(rec));
  EXPECT_EQ(rec.rays, 2 * per);
  EXPECT_NEAR(rec.r, 1e6, 1e6 * 1e-4);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(rec.e[c], pi, 1e-3 * pi) << "channel " << c;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(rec.rot[3 * c + a], 0.0, 0.02 * glm::length(rot));
  }
}

// Ward and Heckbert's translational gradient on a field with a known one: under a ceiling
// whose radiance is linear in position, E(x) = pi (a + b . x), so grad_trans E = pi b.
TEST(IcLookup, TranslationalGradientUnderALinearCeiling) {
  cl::Context& ctx = test::device_context();
  const dev::IcParams ic = record_sum_params();
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  const glm::vec3 b0(0.4f, 0.2f, -0.3f);
  const glm::vec3 b = b0 - glm::dot(b0, n) * n;  // tangent to the ceiling
  const float a = 2.0f, h = 1.0f;
  dev::IcRecord rec = record_at_origin(n);
  cl::Buffer ic_buf(ctx, sizeof(ic), CL_MEM_READ_ONLY, &ic);
  cl::Buffer rec_buf(ctx, sizeof(rec), CL_MEM_READ_WRITE, &rec);
  cl::Buffer rays(ctx, size_t(ic.rays_theta) * ic.rays_phi * 16);
  cl::Kernel k(test::test_program("kernels/ic_test.cl"), "ic_finish_ceiling");
  k.args(0, ic_buf, rec_buf, rays, a, b.x, b.y, b.z, h);
  k.launch(ctx, 1);
  rec_buf.read(&rec, sizeof(rec));
  const double pi = 3.14159265358979;
  const glm::vec3 expected = float(pi) * b;
  std::cout << "[ figures  ] linear ceiling: E " << rec.e[0] << " (expected " << pi * a
            << "), grad_trans (" << rec.trans[0] << ", " << rec.trans[1] << ", " << rec.trans[2]
            << ") expected (" << expected.x << ", " << expected.y << ", " << expected.z << ")\n";
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(rec.e[c], pi * a, 2e-3 * pi * a) << "channel " << c;
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(rec.trans[3 * c + i], expected[i], 0.05 * glm::length(expected))
          << "channel " << c << " axis " << i;
  }
}

// ---------------------------------------------------------------------------------------
// IcFurnace

class IcFurnace : public ::testing::TestWithParam<test::FurnaceCase> {};

TEST_P(IcFurnace, MatchesClosedForm) {
  const test::FurnaceCase c = GetParam();
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  RenderSettings s = test::render_settings("ic", 2, 16);
  s.max_depth = c.max_depth;
  s.ic.rays = 64;
  // Each batch builds its own cache (its seed's), so the batches are independent.
  const BatchMean bm = batch_mean(test::render_batches(scene, s, 24, 5100));
  const double z = (bm.mean - expected) / bm.sigma;
  EXPECT_LT(std::fabs(z), 4.0) << "mean " << bm.mean << " expected " << expected << " sigma "
                               << bm.sigma;
  EXPECT_LT(4.0 * bm.sigma, 0.01 * expected) << "too few samples for a meaningful test";
  std::cout << "[ figures  ] ic furnace rho " << c.rho << " depth " << c.max_depth << ": mean "
            << bm.mean << " expected " << expected << " sigma " << bm.sigma << " z " << z << "\n";
}

INSTANTIATE_TEST_SUITE_P(Cases, IcFurnace,
                         ::testing::Values(test::FurnaceCase{0.5f, 3}, test::FurnaceCase{0.8f, 8}),
                         [](const auto& info) { return test::furnace_case_name(info.param); });

// ---------------------------------------------------------------------------------------
// IcConsistency

TEST(IcConsistency, ErrorFallsWithIcErrorOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, 32, 8192, 4242);
  const double ref_mean = image_mean(ref.mean);
  // A consistent sequence: the interpolation error falls with a, the records' own noise
  // with their rays, and both must fall (at 256 rays the records' noise is the floor from
  // a 0.2 on). At 1024 spp the direct light's pixel noise is about 0.0009 (pt's relMSE at
  // that spp): from a 0.2 on, ic's interpolation error lies under it, so a 0.2 and 0.1 are
  // each held below a 0.4, not below each other.
  double rel[3] = {0.0, 0.0, 0.0};
  int i = 0;
  for (const auto& [a, rays] : {std::pair{0.4f, 256u}, std::pair{0.2f, 1024u}, std::pair{0.1f, 4096u}}) {
    RenderSettings s = test::render_settings("ic", 1024, 32);
    s.ic.error = a;
    s.ic.rays = rays;
    const FilmResult img = test::render(scene, s, 21);
    const double rel_mse = compare_images(img.mean, ref.mean).rel_mse;
    const double ratio = image_mean(img.mean) / ref_mean;
    std::cout << "[ figures  ] ic cornell 32x32, a " << a << ", " << rays << " rays: relMSE "
              << rel_mse << ", mean / reference " << ratio << "\n";
    rel[i++] = rel_mse;
    if (a == 0.2f) {
      EXPECT_NEAR(ratio, 1.0, 0.02);
      s.ic.gradients = false;
      const double without = compare_images(test::render(scene, s, 21).mean, ref.mean).rel_mse;
      std::cout << "[ figures  ] ic cornell 32x32, a 0.2, 1024 rays, without gradients: relMSE "
                << without << "\n";
      EXPECT_LT(rel_mse, without) << "gradients should lower the interpolation error";
    }
  }
  EXPECT_LT(rel[1], 0.8 * rel[0]) << "a 0.2 against 0.4";
  EXPECT_LT(rel[2], 0.8 * rel[0]) << "a 0.1 against 0.4";
}

// The glossy metal block and the smooth glass block: records behind delta surfaces (depth
// > 0), the path-traced rest of the BSDF on the metal (kd = 0) and on glass, misses through
// the glass. Biased, so not a z-test: the image mean within 2 % of pt's, and every 8 x 8
// block's mean within 10 % (the reference's own noise per block is about 1 %).
TEST(IcConsistency, GlossyAndGlassBoxNearPt) {
  const Scene scene = test::cornell_box_glossy_glass();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBoxGlossyGlass, 32, 16384, 4343);
  RenderSettings s = test::render_settings("ic", 1024, 32);
  s.ic.rays = 1024;
  const FilmResult img = test::render(scene, s, 23);
  const double ratio = image_mean(img.mean) / image_mean(ref.mean);
  const double rel_mse = compare_images(img.mean, ref.mean).rel_mse;
  std::cout << "[ figures  ] ic glossy+glass 32x32: mean / reference " << ratio << ", relMSE "
            << rel_mse << "\n";
  EXPECT_NEAR(ratio, 1.0, 0.02);
  double worst = 0.0;
  for (uint32_t by = 0; by < 32; by += 8)
    for (uint32_t bx = 0; bx < 32; bx += 8) {
      double a = 0.0, b = 0.0;
      for (uint32_t y = by; y < by + 8; ++y)
        for (uint32_t x = bx; x < bx + 8; ++x)
          for (int c = 0; c < 3; ++c) {
            a += img.mean.rgb[(size_t(y) * 32 + x) * 3 + c];
            b += ref.mean.rgb[(size_t(y) * 32 + x) * 3 + c];
          }
      if (b > 0.0) worst = std::max(worst, std::fabs(a / b - 1.0));
    }
  std::cout << "[ figures  ] ic glossy+glass 32x32: worst 8x8 block off by " << worst << "\n";
  EXPECT_LT(worst, 0.10);
}

// The plane of Ward and Heckbert's argument: a floor (z = 0, x and y in [-1, 1]) beside a
// white wall at x = -1 that an area light (at x = 0, above the floor's middle, 1.6 x 0.5 m)
// lights; the light faces the wall, so the floor's indirect irradiance, which the cache
// holds, falls steadily from the wall across the whole floor (a long gradient), and the
// camera above sees only the floor (the light edge-on). Records spread wide (a 0.5, up to
// 64 footprints apart) so that interpolation, not the records' own noise (4 096 rays each),
// decides the error.
Scene gradient_plane() {
  Scene scene;
  auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, const Material& m) {
    test::Mesh q;  // a b c d counter-clockwise seen from the side it faces
    q.positions = {a, b, c, d};
    q.triangles = {glm::uvec3(0, 1, 2), glm::uvec3(0, 2, 3)};
    test::add_mesh(scene, q, m);
  };
  Material white;
  white.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  white.metallic = 0.0f;
  white.specular = 0.0f;
  white.double_sided = true;
  quad({-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, white);   // floor, facing +z
  quad({-1, -1, 0}, {-1, 1, 0}, {-1, 1, 1}, {-1, -1, 1}, white);  // wall, facing +x
  Material lamp;
  lamp.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  lamp.emission = glm::vec3(400.0f);
  lamp.metallic = 0.0f;
  lamp.specular = 0.0f;
  lamp.double_sided = false;
  quad({0.0f, -0.8f, 0.5f}, {0.0f, -0.8f, 1.0f}, {0.0f, 0.8f, 1.0f}, {0.0f, 0.8f, 0.5f},
       lamp);  // facing -x, towards the wall
  test::add_camera_on_z(scene, 3.0f, 2.0f * std::atan(1.0f / 3.0f));
  return scene;
}

TEST(IcConsistency, GradientsHalveTheErrorOnAPlane) {
  // The interpolation error alone: every image here has the same seed, so emission and
  // direct light (NEE and the BSDF sample, the same random numbers in each) are identical
  // and two images differ only by kd (E_a - E_b) where both read the cache (the floor is
  // Lambertian: no path-traced rest). The yardstick is a dense cache (a 0.1, 16 384 rays a
  // record), whose records sit about a pixel apart, so that interpolation barely matters.
  const Scene scene = gradient_plane();
  RenderSettings s = test::render_settings("ic", 16, 32);
  s.ic.error = 0.1f;
  s.ic.rays = 16384;
  const FilmResult dense = test::render(scene, s, 25);
  s.ic.error = 0.5f;
  s.ic.max_spacing = 64.0f;
  s.ic.rays = 4096;
  const FilmResult with = test::render(scene, s, 25);
  s.ic.gradients = false;
  const FilmResult without = test::render(scene, s, 25);
  const double e_with = compare_images(with.mean, dense.mean).rel_mse;
  const double e_without = compare_images(without.mean, dense.mean).rel_mse;
  std::cout << "[ figures  ] ic gradient plane 32x32, a 0.5 against a 0.1: relMSE with gradients "
            << e_with << ", without " << e_without << "\n";
  EXPECT_LT(e_with, 0.5 * e_without) << "gradients should halve the interpolation error";
}

// ---------------------------------------------------------------------------------------
// IcOptions

using test::parse_error;

TEST(IcOptions, BadValuesAreUsageErrors) {
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-error", "0.1", "--ic-rays", "64",
                         "--ic-min-spacing", "2", "--ic-max-spacing", "8", "--ic-no-gradients",
                         "--ic-show-records"}),
            ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-error", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-error", "-0.2"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-error", "1.5"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-error", "nan"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-rays", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-min-spacing", "4",
                         "--ic-max-spacing", "2"}),
            ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-min-spacing", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-max-spacing", "inf"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--hemisphere", "cosine"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--branching", "2"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--time", "5", "--checkpoint", "c.ckpt"}),
            ExitCode::Usage);  // the refinement's rounds depend on the clock
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--spp", "5", "--checkpoint", "c.ckpt"}),
            ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--ic-error", "0.1"}), ExitCode::Usage);  // not ic
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pt", "--ic-show-records"}), ExitCode::Usage);
}

// ---------------------------------------------------------------------------------------
// IcCli

// Ctrl-C during the cache's refinement (a quarter of --time: 15 s here) ends it: the first
// pass then completes, the render is saved and clpt exits 130 in seconds, not after the 15.
TEST(IcCli, InterruptEndsTheRefinement) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt_ic_int_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  // The kernels first (a render of one sample): with a cold kernel cache their build (22 s on
  // PoCL) comes before "rendering " and would count against the interrupt's time. The test
  // failed so whenever it was the suite's first ic render.
  const test::RunResult warm = test::run_clpt({scene, "--device", "pocl", "--integrator", "ic",
                                               "--resolution", "32x32", "--spp", "1", "-o",
                                               (dir / "warm.exr").string()});
  ASSERT_EQ(warm.exit_code, 0) << warm.err;
  const auto t0 = std::chrono::steady_clock::now();
  const test::RunResult r = test::run_clpt({scene, "--device", "pocl", "--integrator", "ic",
                                            "--resolution", "32x32", "--time", "60", "-o",
                                            (dir / "i.exr").string()},
                                           "rendering ", 1.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_LT(seconds, 12.0) << "the refinement went on after Ctrl-C";
  EXPECT_TRUE(std::filesystem::exists(dir / "i.exr")) << "the interrupted render must be saved";
  std::filesystem::remove_all(dir);
}

TEST(IcCli, StatsMarksAndDeterminism) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt_ic_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--integrator", "ic", "--resolution", "32x32", "--spp", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_clpt_stats(dir, name, scene, args);
  };
  const nlohmann::json a = run("a", {}), b = run("b", {});
  ASSERT_FALSE(a.is_null() || b.is_null());
  const nlohmann::json& ic = a["ic"];
  const uint64_t records = ic["records"].get<uint64_t>();
  EXPECT_GT(records, 10u);
  EXPECT_LE(records, ic["candidates"].get<uint64_t>());
  EXPECT_EQ(ic["rays_per_record"].get<uint32_t>(), 252u);  // 256 asked: 9 x 28
  EXPECT_EQ(ic["placement_passes"].get<uint32_t>(), 4u);  // steps 4, 2, 1, then 1 jittered
  EXPECT_GT(ic["lookups"].get<uint64_t>(), 32u * 32u);      // most of 2 samples per pixel
  EXPECT_LE(ic["lookups"].get<uint64_t>(), 2u * 32u * 32u);
  EXPECT_LT(ic["lookup_misses"].get<uint64_t>(), ic["lookups"].get<uint64_t>() / 10);
  EXPECT_GT(ic["records_per_lookup"].get<double>(), 1.0);
  EXPECT_GT(ic["device_bytes"].get<uint64_t>(), records * sizeof(dev::IcRecord));
  EXPECT_EQ(b["ic"]["records"].get<uint64_t>(), records);
  const Image ia = read_image(dir / "a.exr"), ib = read_image(dir / "b.exr");
  EXPECT_EQ(ia.rgb, ib.rgb) << "one seed, one cache, one image";
  const nlohmann::json m = run("marks", {"--ic-show-records"});
  ASSERT_FALSE(m.is_null());
  const Image im = read_image(dir / "marks.exr");
  size_t marked = 0;
  for (size_t i = 0; i < im.rgb.size(); i += 3)
    marked += im.rgb[i] == 1.0f && im.rgb[i + 1] == 0.0f && im.rgb[i + 2] == 0.0f;
  // A mark per record's pixel: the centre passes give each pixel at most one record, the
  // jittered pass may add a second to a pixel.
  const uint64_t marked_records = m["ic"]["records"].get<uint64_t>();
  EXPECT_LE(marked, marked_records);
  EXPECT_GT(marked, marked_records * 3 / 4);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clpt::ic_test
