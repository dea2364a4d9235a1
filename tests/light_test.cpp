// The light interface (kernels/light/), on the device through tests/kernels/light_test.cl,
// and lights in whole renders:
//   LightSampling  chi-square of NEE directions against light_pdf_w (a triangle light; the
//                  environment map in (u, v) on a texel-aligned grid and on the sphere; the
//                  constant background); light_illuminate's pdf equals light_pdf_w /
//                  light_env_pdf_w found by tracing; each light's emitted power (light_emit)
//                  equals its closed form; the spot falloff integral; the env mapping.
//   LightRender    closed forms: a convex diffuse object under a uniform environment shows
//                  rho L; a diffuse plane under a point, spot and directional light; NEE of an
//                  environment map agrees with BSDF sampling (cross-strategy z-test).
//   LightCli       --env / --background errors and a render through the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numeric>

#include "bvh/bvh.h"
#include "io/image_io.h"
#include "render/renderer.h"
#include "render/scene_buffers.h"
#include "stats/image_stats.h"
#include "support/chi2.h"
#include "support/device.h"
#include "support/mesh.h"
#include "support/run.h"
#include "support/scenes.h"

namespace clpt::light_test {
namespace {
namespace fs = std::filesystem;
using test::Chi2Grid;
using test::Chi2Options;
using test::Chi2Result;

constexpr double kPi = 3.14159265358979323846;
constexpr uint32_t kSamples = 1u << 20;

double lum(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

double suite_alpha() {
  const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
  return test::sidak_alpha(0.01, suite ? suite->total_test_count() : 1);
}

void print_result(const Chi2Result& r) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::cout << "[ chi2     ] " << (info ? info->name() : "") << ": " << r.summary() << "\n";
}

Material diffuse(float rho, glm::vec3 emission = glm::vec3(0.0f), bool double_sided = false) {
  Material m;
  m.base_color = glm::vec4(rho, rho, rho, 1.0f);
  m.metallic = 0.0f;
  m.specular = 0.0f;  // exactly Lambertian
  m.emission = emission;
  m.double_sided = double_sided;
  return m;
}

// A triangle of zero area spanning [-1, 1]^3: gives the scene bounds (radius sqrt(3)) and is
// never hit.
void add_bounds_only(Scene& s) {
  test::Mesh m;
  m.positions = {{-1, -1, -1}, {1, 1, 1}, {0, 0, 0}};
  m.triangles = {{0, 1, 2}};
  test::add_mesh(s, m, diffuse(0.5f));
}

// A small equirectangular map with structure: a dim gradient, a bright warm blob, and a block
// of black texels (which must never be sampled).
Image test_env_map(uint32_t w = 32, uint32_t h = 16) {
  Image img(w, h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const double u = (x + 0.5) / w, v = (y + 0.5) / h;
      const double blob = 20.0 * std::exp(-((u - 0.3) * (u - 0.3) + (v - 0.35) * (v - 0.35)) / 0.005);
      float* p = img.pixel(x, y);
      p[0] = float(0.2 + 0.5 * u + blob);
      p[1] = float(0.3 + 0.2 * v + 0.6 * blob);
      p[2] = float(0.5 + 0.1 * u * v + 0.2 * blob);
      if (x >= 20 && x < 24 && y >= 8 && y < 12) p[0] = p[1] = p[2] = 0.0f;
    }
  return img;
}

// The scene on the device, as the renderer builds it.
struct DeviceScene {
  Bvh bvh;
  FlatScene flat;
  std::unique_ptr<SceneBuffers> buffers;
  DeviceScene(const Scene& scene, const Environment& env)
      : bvh(build_bvh(scene.positions, scene.triangles)), flat(flatten_scene(scene, bvh, env)),
        buffers(std::make_unique<SceneBuffers>(test::device_context(), flat)) {}
};

const cl::Program& light_program() {
  return test::test_program("kernels/light_test.cl");
}

struct NeeSamples {
  std::vector<glm::vec4> dir;  // wi, pdf_w
  std::vector<glm::vec4> le;   // Le, light index
  std::vector<float> check;    // the same light's pdf found by tracing; -1: not checked
};

NeeSamples illuminate(const DeviceScene& ds, glm::vec3 p, uint32_t seed, uint32_t n) {
  cl::Context& ctx = test::device_context();
  cl::Buffer dir(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "dirs");
  cl::Buffer le(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "le");
  cl::Buffer check(ctx, n * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "check");
  cl::Kernel k(light_program(), "light_illuminate_samples");
  const cl_uint a = ds.buffers->bind(k, 0);
  k.args(a, glm::vec4(p, 0.0f), cl_uint(seed), dir, le, check, cl_uint(n));
  k.launch(ctx, n);
  return {dir.read_vector<glm::vec4>(n), le.read_vector<glm::vec4>(n), check.read_vector<float>(n)};
}

std::vector<double> pdf_at(const DeviceScene& ds, glm::vec3 p, const std::vector<glm::dvec3>& dirs) {
  cl::Context& ctx = test::device_context();
  std::vector<glm::vec4> d(dirs.size());
  for (size_t i = 0; i < dirs.size(); ++i) d[i] = glm::vec4(glm::vec3(dirs[i]), 0.0f);
  cl::Buffer in = cl::Buffer::from_vector(ctx, d);
  cl::Buffer out(ctx, d.size() * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "pdf");
  cl::Kernel k(light_program(), "light_pdf_at");
  const cl_uint a = ds.buffers->bind(k, 0);
  k.args(a, glm::vec4(p, 0.0f), in, out, cl_uint(d.size()));
  k.launch(ctx, d.size());
  const std::vector<float> f = out.read_vector<float>(d.size());
  return std::vector<double>(f.begin(), f.end());
}

Chi2Options chi2_options() {
  Chi2Options o;
  o.alpha = suite_alpha();
  return o;
}

// The host's mirror of kernels/light/environment.cl's mapping (map space = world space at
// rotation 0): u = 1/2 + atan2(x, -z) / 2 pi, v = acos(y) / pi.
glm::dvec2 env_uv(const glm::dvec3& w) {
  double u = 0.5 + std::atan2(w.x, -w.z) / (2.0 * kPi);
  u -= std::floor(u);
  return {u, std::acos(std::max(-1.0, std::min(1.0, w.y))) / kPi};
}

// --------------------------------------------------------------------------------------
// LightSampling

TEST(LightSampling, TriangleLightChi2) {
  Scene s;
  test::Mesh tri;  // seen from the origin, facing it (normal towards -z)
  tri.positions = {{-1.5f, -1.0f, 1.0f}, {0.0f, 1.5f, 1.0f}, {1.5f, -1.0f, 1.0f}};
  tri.triangles = {{0, 1, 2}};
  test::add_mesh(s, tri, diffuse(0.5f, glm::vec3(1.0f, 2.0f, 0.5f)));
  const DeviceScene ds(s, {});
  ASSERT_EQ(ds.flat.lights.size(), 1u);
  const glm::vec3 p(0.1f, 0.0f, 0.0f);
  const NeeSamples ns = illuminate(ds, p, 7, kSamples);
  test::SphereBins bins;
  bins.z_min = 0.0;  // the triangle is in the upper half (z > 0)
  bins.subdivisions = 6;
  const Chi2Grid grid = Chi2Grid::sphere(bins);
  Chi2Options o = chi2_options();
  o.integral_tolerance = 2e-3;  // the pdf jumps on the triangle's edges inside cells
  const Chi2Result r = test::chi2_test(grid, ns.dir, pdf_at(ds, p, grid.nodes()), o);
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report;
  size_t checked = 0;
  for (size_t i = 0; i < ns.le.size(); ++i) {
    EXPECT_NEAR(ns.le[i].x, 1.0f, 1e-6f);  // the emission at the sampled point
    EXPECT_NEAR(ns.le[i].y, 2.0f, 1e-6f);
    if (ns.check[i] < 0.0f) continue;
    ++checked;
    EXPECT_NEAR(ns.check[i], ns.dir[i].w, 1e-3f * ns.dir[i].w) << "sample " << i;
  }
  EXPECT_GT(checked, kSamples * 99 / 100);
}

TEST(LightSampling, EnvironmentMapChi2InUv) {
  // In (u, v) the density is constant on each texel: a grid aligned with the texels
  // integrates it exactly. Directions are mapped back to (u, v) on the host (rotation 0).
  Scene s;
  add_bounds_only(s);
  Environment env;
  env.map = test_env_map();
  const DeviceScene ds(s, env);
  ASSERT_EQ(ds.flat.lights.size(), 1u);
  const NeeSamples ns = illuminate(ds, glm::vec3(0.0f), 11, kSamples);
  std::vector<glm::vec4> uv(ns.dir.size());
  size_t black = 0;
  for (size_t i = 0; i < uv.size(); ++i) {
    const glm::dvec2 t = env_uv(glm::dvec3(ns.dir[i]));
    uv[i] = glm::vec4(float(t.x), float(t.y), 0.0f, 0.0f);
    const uint32_t x = uint32_t(t.x * 32), y = uint32_t(t.y * 16);
    black += x >= 20 && x < 24 && y >= 8 && y < 12;
  }
  EXPECT_EQ(black, 0u) << "samples in black texels";
  // pdf_uv from the map itself: luminance x sin(theta) of the row centre, normalised.
  const Image map = test_env_map();
  std::vector<double> f(32 * 16);
  double total = 0.0;
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 32; ++x) {
      const float* p = map.pixel(x, y);
      f[y * 32 + x] = lum(glm::dvec3(p[0], p[1], p[2])) * std::sin(kPi * (y + 0.5) / 16);
      total += f[y * 32 + x];
    }
  const Chi2Grid grid = Chi2Grid::plane(test::PlaneDomain::Square, 64, 32);
  const Chi2Result r = test::chi2_test(grid, uv, [&](const glm::dvec3& q) {
    const uint32_t x = std::min(uint32_t(q.x * 32), 31u), y = std::min(uint32_t(q.y * 16), 15u);
    return f[y * 32 + x] * 512.0 / total;
  }, chi2_options());
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report;
  // pdf_w = pdf_uv / (2 pi^2 sin theta), and light_env_pdf_w agrees with the sample's pdf.
  for (size_t i = 0; i < ns.dir.size(); i += 97) {
    const glm::dvec3 w(ns.dir[i]);
    const glm::dvec2 t = env_uv(w);
    const uint32_t x = std::min(uint32_t(t.x * 32), 31u), y = std::min(uint32_t(t.y * 16), 15u);
    const double expect = f[y * 32 + x] * 512.0 / total / (2.0 * kPi * kPi * std::sqrt(1.0 - w.y * w.y));
    EXPECT_NEAR(ns.dir[i].w, expect, 2e-3 * expect) << "sample " << i;
    EXPECT_NEAR(ns.check[i], ns.dir[i].w, 1e-5f * ns.dir[i].w) << "sample " << i;
  }
}

TEST(LightSampling, EnvironmentMapChi2OnSphere) {
  // The same map turned by 70 degrees about +y, in solid angle: light_env_pdf_w at the grid
  // nodes must integrate to 1 and match the directions' histogram.
  Scene s;
  add_bounds_only(s);
  Environment env;
  env.map = test_env_map();
  env.rotation = float(70.0 * kPi / 180.0);
  const DeviceScene ds(s, env);
  const NeeSamples ns = illuminate(ds, glm::vec3(0.0f), 13, kSamples);
  // The chi-square grid's pole is +z; the map's is +y: rotate y -> z for the test.
  std::vector<glm::vec4> d(ns.dir.size());
  for (size_t i = 0; i < d.size(); ++i)
    d[i] = glm::vec4(ns.dir[i].x, -ns.dir[i].z, ns.dir[i].y, ns.dir[i].w);
  test::SphereBins bins;
  bins.z_bins = 32;
  bins.phi_bins = 64;
  bins.subdivisions = 6;
  const Chi2Grid grid = Chi2Grid::sphere(bins);
  std::vector<glm::dvec3> nodes(grid.nodes().size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const glm::dvec3& q = grid.nodes()[i];
    nodes[i] = glm::dvec3(q.x, q.z, -q.y);
  }
  Chi2Options o = chi2_options();
  o.integral_tolerance = 2e-3;
  const Chi2Result r = test::chi2_test(grid, d, pdf_at(ds, glm::vec3(0.0f), nodes), o);
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report << " outside " << r.outside_samples << " zero pdf "
                        << r.zero_pdf_samples;
}

TEST(LightSampling, ConstantBackgroundIsUniform) {
  Scene s;
  add_bounds_only(s);
  Environment env;
  env.background = glm::vec3(0.5f, 1.0f, 2.0f);
  const DeviceScene ds(s, env);
  ASSERT_EQ(ds.flat.lights.size(), 1u);
  const NeeSamples ns = illuminate(ds, glm::vec3(0.0f), 17, kSamples);
  const Chi2Grid grid = Chi2Grid::sphere();
  const Chi2Result r = test::chi2_test(grid, ns.dir, pdf_at(ds, glm::vec3(0.0f), grid.nodes()),
                                       chi2_options());
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report;
  for (size_t i = 0; i < 1000; ++i) {
    EXPECT_NEAR(ns.le[i].x, 0.5f, 1e-6f);
    EXPECT_NEAR(ns.le[i].z, 2.0f, 1e-6f);
    EXPECT_NEAR(ns.dir[i].w, 1.0 / (4.0 * kPi), 1e-6);
  }
}

// A scene with one light of every type, and the selection/consistency checks across them.
Scene every_light_scene() {
  Scene s;
  add_bounds_only(s);
  test::Mesh one;  // one-sided, facing +y, area 0.5
  one.positions = {{2.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 1.0f}, {3.0f, 0.0f, 0.0f}};
  one.triangles = {{0, 1, 2}};
  test::add_mesh(s, one, diffuse(0.5f, glm::vec3(1.0f, 2.0f, 3.0f)));
  test::Mesh two;  // double-sided, area 2
  two.positions = {{-2.0f, 1.0f, -1.0f}, {-2.0f, 1.0f, 1.0f}, {-2.0f, -1.0f, -1.0f}};
  two.triangles = {{0, 1, 2}};
  test::add_mesh(s, two, diffuse(0.5f, glm::vec3(0.5f), true));
  PunctualLight point;
  point.type = PunctualLight::Type::Point;
  point.color = glm::vec3(1.0f, 0.5f, 0.25f);
  point.intensity = 3.0f;
  point.position = glm::vec3(0.0f, 3.0f, 0.0f);
  s.lights.push_back(point);
  PunctualLight spot;
  spot.type = PunctualLight::Type::Spot;
  spot.intensity = 10.0f;
  spot.position = glm::vec3(0.0f, -3.0f, 0.0f);
  spot.direction = glm::vec3(0.0f, 1.0f, 0.0f);
  spot.inner_cone = 0.3f;
  spot.outer_cone = 0.7f;
  s.lights.push_back(spot);
  PunctualLight sun;
  sun.type = PunctualLight::Type::Directional;
  sun.intensity = 2.0f;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  s.lights.push_back(sun);
  return s;
}

TEST(LightSampling, IlluminatePdfEqualsLightPdf) {
  Environment env;
  env.map = test_env_map();
  env.rotation = 1.0f;
  const DeviceScene ds(every_light_scene(), env);
  ASSERT_EQ(ds.flat.lights.size(), 6u);
  const NeeSamples ns = illuminate(ds, glm::vec3(0.2f, 0.5f, 0.3f), 23, 1u << 16);
  std::vector<size_t> chosen(6, 0), checked(6, 0);
  for (size_t i = 0; i < ns.dir.size(); ++i) {
    const uint32_t li = uint32_t(ns.le[i].w);
    ASSERT_LT(li, 6u);
    ++chosen[li];
    const dev::Light& l = ds.flat.lights[li];
    const bool delta = l.type == dev::LIGHT_POINT || l.type == dev::LIGHT_SPOT ||
                       l.type == dev::LIGHT_DIRECTIONAL;
    if (delta && ns.dir[i].w > 0.0f) {
      EXPECT_FLOAT_EQ(ns.dir[i].w, l.pdf_select);
    }
    if (ns.check[i] < 0.0f || !(ns.dir[i].w > 0.0f)) continue;
    ++checked[li];
    EXPECT_NEAR(ns.check[i], ns.dir[i].w, 1e-3f * ns.dir[i].w) << "light " << li << " sample " << i;
  }
  // Selection frequencies follow pdf_select (binomial, 5 sigma).
  for (size_t li = 0; li < 6; ++li) {
    const double p = ds.flat.lights[li].pdf_select, n = double(ns.dir.size());
    EXPECT_NEAR(double(chosen[li]), n * p, 5.0 * std::sqrt(n * p * (1 - p)) + 1.0) << "light " << li;
    if (ds.flat.lights[li].type == dev::LIGHT_TRIANGLE ||
        ds.flat.lights[li].type == dev::LIGHT_ENVIRONMENT) {
      EXPECT_GT(checked[li], chosen[li] / 4) << "light " << li;
    }
  }
}

TEST(LightSampling, SpotFalloffIntegral) {
  // Against Simpson's rule on the glTF formula itself.
  auto numeric = [](double co, double ci) {
    const double scale = 1.0 / std::max(0.001, ci - co);
    auto f = [&](double c) {
      const double t = std::min(1.0, std::max(0.0, (c - co) * scale));
      return t * t;
    };
    const int n = 2000000;
    double sum = f(-1.0) + f(1.0);
    for (int i = 1; i < n; ++i) sum += f(-1.0 + 2.0 * i / n) * (i % 2 ? 4.0 : 2.0);
    return sum * (2.0 / n) / 3.0;
  };
  for (auto [inner, outer] : {std::pair{0.0, 0.785398}, {0.3, 0.7}, {0.5, 0.5005}, {0.0, 1.5707963},
                              {1.2, 1.5707963}}) {
    const double co = std::cos(outer), ci = std::cos(inner);
    EXPECT_NEAR(spot_falloff_integral(co, ci), numeric(co, ci), 1e-7) << inner << " " << outer;
  }
}

TEST(LightSampling, EmittedPowerMatchesClosedForm) {
  Environment env;
  env.map = test_env_map();
  env.scale = 0.5f;
  const Scene scene = every_light_scene();
  const DeviceScene ds(scene, env);
  ASSERT_EQ(ds.flat.lights.size(), 6u);
  const uint32_t n = 1u << 22;
  cl::Context& ctx = test::device_context();
  cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "emit");
  cl::Buffer dirs(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "dirs");
  cl::Kernel k(light_program(), "light_emit_samples");
  const cl_uint a = ds.buffers->bind(k, 0);
  k.args(a, cl_uint(31), out, dirs, cl_uint(n));
  k.launch(ctx, n);
  const std::vector<glm::vec4> v = out.read_vector<glm::vec4>(n);
  // Per light: the mean of X * 1{light i} over all samples estimates its power.
  std::vector<double> sum(6, 0.0), sum2(6, 0.0);
  for (const glm::vec4& s : v) {
    const double x = lum(glm::dvec3(s));
    ASSERT_TRUE(std::isfinite(x));
    sum[size_t(s.w)] += x;
    sum2[size_t(s.w)] += x * x;
  }
  const double r = ds.flat.info.bounds_radius;
  // Closed forms, computed here independently of the renderer.
  double env_integral = 0.0;  // integral of luminance over the sphere, texel by texel
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 32; ++x) {
      const float* p = env.map.pixel(x, y);
      const double sr = (std::cos(kPi * y / 16) - std::cos(kPi * (y + 1) / 16)) * 2.0 * kPi / 32;
      env_integral += lum(glm::dvec3(p[0], p[1], p[2])) * sr * env.scale;
    }
  const double co = std::cos(0.7), ci = std::cos(0.3);
  // Spot: 2 pi I times the integral of the falloff over cos(theta): a quadratic ramp from
  // cos_outer to cos_inner (integral (ci - co) / 3), then 1.
  const double expected[6] = {
      lum({1.0, 2.0, 3.0}) * 0.5 * kPi,           // one-sided triangle, area 0.5
      lum({0.5, 0.5, 0.5}) * 2.0 * kPi * 2.0,     // double-sided, area 2
      4.0 * kPi * lum({3.0, 1.5, 0.75}),          // point
      2.0 * kPi * 10.0 * ((ci - co) / 3.0 + (1.0 - ci)),  // spot
      kPi * r * r * 2.0,                          // directional
      kPi * r * r * env_integral,                 // environment
  };
  for (size_t i = 0; i < 6; ++i) {
    const double mean = sum[i] / n;
    const double var = std::max(0.0, sum2[i] / n - mean * mean);
    const double sigma = std::sqrt(var / n);
    std::cout << "[ power    ] light " << i << " (type " << ds.flat.lights[i].type << "): " << mean
              << " expected " << expected[i] << " sigma " << sigma << "\n";
    EXPECT_NEAR(mean, expected[i], 4.5 * sigma + 1e-4 * expected[i]) << "light " << i;
    EXPECT_LT(sigma, 0.01 * expected[i]) << "too few samples for light " << i;
  }
}

// An emissive texture shapes the triangles' selection weights (host/render/light_table.cpp):
// a texture black on its left half and white on its right; triangle A maps into the black
// half, B into the white one. Texture mean luminance 0.5, so A's weight is 0 + 0.05 * 0.5 and
// B's 1 + 0.05 * 0.5 (corners and centroid sampled): A keeps a small probability (it could
// emit between its samples), B takes nearly all.
TEST(LightSampling, EmissiveTextureShapesSelection) {
  Scene scene;
  Texture tex;
  tex.width = 2;
  tex.height = 1;
  tex.texels = {0xff000000u, 0xffffffffu};
  scene.textures.push_back(tex);
  Material m;
  m.emission = glm::vec3(1.0f);
  m.emissive_texture.texture = 0;
  scene.materials.push_back(m);
  for (int k = 0; k < 2; ++k) {
    const float x = float(k) * 2.0f, u0 = k == 0 ? 0.05f : 0.55f;
    const uint32_t b = uint32_t(scene.positions.size());
    scene.positions.insert(scene.positions.end(), {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}});
    scene.normals.insert(scene.normals.end(), 3, glm::vec3(0.0f));
    scene.uvs.insert(scene.uvs.end(), {{u0, 0.1f}, {u0 + 0.4f, 0.1f}, {u0, 0.9f}});
    scene.triangles.emplace_back(b, b + 1, b + 2);
    scene.triangle_materials.push_back(0);
  }
  const Bvh bvh = build_bvh(scene.positions, scene.triangles);
  const FlatScene flat = flatten_scene(scene, bvh);
  ASSERT_EQ(flat.lights.size(), 2u);
  // Leaf order may differ from input order: find each by its first vertex.
  double pa = 0.0, pb = 0.0;
  for (const dev::Light& l : flat.lights)
    (flat.triangles[l.triangle].v[0] == 0 ? pa : pb) = l.pdf_select;
  EXPECT_NEAR(pa, 0.025 / 1.05, 1e-6);
  EXPECT_NEAR(pb, 1.025 / 1.05, 1e-6);
}

TEST(LightSampling, EnvironmentMappingCentreIsMinusZ) {
  // The map's centre texel is seen looking down -z; +x is to its right (u grows); the top row
  // is +y. With --env-rotate 90 the centre turns to -x (the rotation takes +z towards +x).
  Scene s;
  add_bounds_only(s);
  Environment env;
  env.map = Image(4, 2);
  const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}};  // by column
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) env.map.pixel(x, y)[c] = colours[x][c] * (y == 0 ? 2.0f : 1.0f);
  auto look = [&](float rotation_deg, std::vector<glm::vec4> dirs) {
    env.rotation = float(rotation_deg * kPi / 180.0);
    const DeviceScene ds(s, env);
    cl::Context& ctx = test::device_context();
    cl::Buffer in = cl::Buffer::from_vector(ctx, dirs);
    cl::Buffer out(ctx, dirs.size() * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "L");
    cl::Kernel k(light_program(), "env_radiance_at");
    const cl_uint a = ds.buffers->bind(k, 0);
    k.args(a, in, out, cl_uint(dirs.size()));
    k.launch(ctx, dirs.size());
    return out.read_vector<glm::vec4>(dirs.size());
  };
  const float e = 0.05f;  // just right of the centre line u = 1/2: column 2
  const std::vector<glm::vec4> r0 = look(0.0f, {{e, 0.1f, -1, 0}, {-e, -0.1f, -1, 0}, {1, 0.1f, e, 0}, {-e, 0.1f, 1, 0}});
  EXPECT_EQ(glm::vec3(r0[0]), glm::vec3(0, 0, 2));  // -z, slightly +x and up: column 2, top row
  EXPECT_EQ(glm::vec3(r0[1]), glm::vec3(0, 1, 0));  // -z, slightly -x and down: column 1, bottom
  EXPECT_EQ(glm::vec3(r0[2]), glm::vec3(2, 2, 0));  // +x: u = 3/4 +, column 3
  EXPECT_EQ(glm::vec3(r0[3]), glm::vec3(2, 0, 0));  // +z, slightly -x: u just above 0, column 0
  const std::vector<glm::vec4> r90 = look(90.0f, {{-1, 0.1f, -e, 0}});
  EXPECT_EQ(glm::vec3(r90[0]), glm::vec3(0, 0, 2));  // the centre has turned to -x
}

// --------------------------------------------------------------------------------------
// LightRender

struct RenderCase {
  const char* name;
  uint32_t direct;
  bool map;  // a uniform environment map instead of the constant background
};
void PrintTo(const RenderCase& c, std::ostream* os) { *os << c.name; }

class ConvexEnvFurnace : public ::testing::TestWithParam<RenderCase> {};

TEST_P(ConvexEnvFurnace, ShowsRhoTimesL) {
  // A convex diffuse object sees only the environment: one bounce, L_o = rho L exactly. The
  // camera is close enough that the sphere fills its whole view.
  constexpr float kRho = 0.6f;
  const glm::vec3 L(1.0f, 0.5f, 0.25f);
  Scene s;
  test::add_mesh(s, test::icosphere(glm::vec3(0.0f), 1.0f, 3), diffuse(kRho));
  test::add_camera_on_z(s, 1.6f, 0.6f);
  RenderSettings rs;
  rs.width = rs.height = 16;
  rs.spp = 256;
  rs.seed = 3;
  rs.direct = GetParam().direct;
  std::string env_file;
  if (GetParam().map) {
    Image m(8, 4);
    for (uint32_t i = 0; i < 32; ++i)
      for (int c = 0; c < 3; ++c) m.rgb[i * 3 + c] = 4.0f * L[c];
    env_file = (fs::temp_directory_path() / ("light-uniform-env-" + std::to_string(::getpid()) + ".exr")).string();
    write_image(env_file, m, {});
    rs.env_file = env_file;
    rs.env_scale = 0.25f;
    rs.env_rotation = 33.0f;
  } else {
    rs.background = L;
  }
  Renderer r(test::device_context(), s, rs);
  const FilmResult f = r.render().film;
  if (!env_file.empty()) fs::remove(env_file);
  ASSERT_EQ(f.dropped_samples, 0u);
  Image ref(16, 16), ref_var(16, 16);
  for (uint32_t i = 0; i < 256; ++i)
    for (int c = 0; c < 3; ++c) ref.rgb[i * 3 + c] = kRho * L[c];
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  const ZTestResult z = z_test(f.mean, &v, ref, &ref_var);
  EXPECT_GE(z.pass_fraction(), 0.9975) << z.failed() << " of " << z.tested << " fail, max |z| " << z.max_abs_z;
  for (int c = 0; c < 3; ++c) {
    double m = 0.0, var = 0.0;
    for (uint32_t i = 0; i < 256; ++i) m += f.mean.rgb[i * 3 + c], var += v.rgb[i * 3 + c];
    m /= 256.0;
    const double sigma = std::sqrt(var) / 256.0;
    std::cout << "[ furnace  ] channel " << c << ": " << m << " expected " << kRho * L[c] << " sigma " << sigma << "\n";
    EXPECT_NEAR(m, kRho * L[c], 4.0 * sigma + 1e-4 * L[c]) << "channel " << c;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Lights, ConvexEnvFurnace,
    ::testing::Values(RenderCase{"background_mis", dev::DIRECT_MIS, false},
                      RenderCase{"background_light", dev::DIRECT_LIGHT, false},
                      RenderCase{"background_bsdf", dev::DIRECT_BSDF, false},
                      RenderCase{"map_mis", dev::DIRECT_MIS, true},
                      RenderCase{"map_light", dev::DIRECT_LIGHT, true}),
    [](const auto& info) { return std::string(info.param.name); });

// A diffuse floor (y = 0) seen from straight above by an orthographic camera over
// [-0.5, 0.5]^2, lit by one punctual light. The expected pixel is the average over its
// footprint of rho / pi * E(x, z), integrated on a 16 x 16 grid (the image is symmetric in
// x and z, so the camera's orientation within the plane does not matter).
struct PunctualCase {
  const char* name;
  PunctualLight::Type type;
  uint32_t direct;
};
void PrintTo(const PunctualCase& c, std::ostream* os) { *os << c.name; }
class PunctualClosedForm : public ::testing::TestWithParam<PunctualCase> {};

TEST_P(PunctualClosedForm, FloorRadiance) {
  constexpr float kRho = 0.5f, kH = 1.0f;
  const PunctualCase pc = GetParam();
  Scene s;
  test::Mesh floor;
  floor.positions = {{-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}};
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  test::add_mesh(s, floor, diffuse(kRho));
  PunctualLight l;
  l.type = pc.type;
  l.color = glm::vec3(1.0f, 0.8f, 0.6f);
  l.intensity = 3.0f;
  l.position = glm::vec3(0.0f, kH, 0.0f);
  l.direction = pc.type == PunctualLight::Type::Directional ? glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f))
                                                             : glm::vec3(0.0f, -1.0f, 0.0f);
  l.inner_cone = 0.2f;
  l.outer_cone = 0.4f;
  s.lights.push_back(l);
  Camera cam;
  cam.type = Camera::Type::Orthographic;
  cam.xmag = cam.ymag = 0.5f;
  cam.camera_to_world = glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, -1, 0),
                                  glm::vec4(0, 1, 0, 0), glm::vec4(0, 2, 0, 1));
  s.cameras.push_back(cam);
  constexpr uint32_t kSize = 16;
  RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.spp = 64;
  rs.seed = 9;
  rs.max_depth = 1;
  rs.direct = pc.direct;
  Renderer r(test::device_context(), s, rs);
  const FilmResult f = r.render().film;
  ASSERT_EQ(f.dropped_samples, 0u);

  const double co = std::cos(0.4), ci = std::cos(0.2);
  auto irradiance = [&](double x, double z) {  // per unit colour x intensity
    if (pc.type == PunctualLight::Type::Directional) return -double(l.direction.y);
    const double d2 = x * x + kH * kH + z * z, d = std::sqrt(d2), cos_t = kH / d;
    double falloff = 1.0;
    if (pc.type == PunctualLight::Type::Spot) {
      const double t = std::min(1.0, std::max(0.0, (cos_t - co) / (ci - co)));
      falloff = t * t;
    }
    return falloff * cos_t / d2;
  };
  Image ref(kSize, kSize), ref_var(kSize, kSize);
  double max_rel = 0.0;
  for (uint32_t py = 0; py < kSize; ++py)
    for (uint32_t px = 0; px < kSize; ++px) {
      // Mean and variance over the pixel's footprint: each sample is exact for its film
      // point (a delta light, one bounce), so the variance of the pixel's mean is the
      // variance of the footprint divided by spp; the test uses that, not the estimate.
      double e = 0.0, e2 = 0.0;
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i) {
          const double q = irradiance(-0.5 + (px + (i + 0.5) / 32.0) / kSize, -0.5 + (py + (j + 0.5) / 32.0) / kSize);
          e += q;
          e2 += q * q;
        }
      e /= 1024.0;
      e2 /= 1024.0;
      for (int c = 0; c < 3; ++c) {
        const double k = kRho / kPi * l.intensity * l.color[c];
        ref.pixel(px, py)[c] = float(k * e);
        ref_var.pixel(px, py)[c] = float(k * k * std::max(0.0, e2 - e * e) / double(rs.spp));
        const double got = f.mean.pixel(px, py)[c], want = ref.pixel(px, py)[c];
        if (want > 1e-3) max_rel = std::max(max_rel, std::fabs(got - want) / want);
      }
    }
  const ZTestResult z = z_test(f.mean, nullptr, ref, &ref_var);
  std::cout << "[ punctual ] " << pc.name << ": max relative error " << max_rel << ", max |z| "
            << z.max_abs_z << "\n";
  EXPECT_GE(z.pass_fraction(), 0.9975) << z.failed() << " of " << z.tested << " fail, max |z| " << z.max_abs_z;
  double m = 0.0, rm = 0.0, var = 0.0;
  for (size_t i = 0; i < ref.rgb.size(); ++i) m += f.mean.rgb[i], rm += ref.rgb[i], var += ref_var.rgb[i];
  EXPECT_NEAR(m, rm, 4.0 * std::sqrt(var) + 1e-4 * rm) << "image sum";
  EXPECT_GT(rm, 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Lights, PunctualClosedForm,
    ::testing::Values(PunctualCase{"point_mis", PunctualLight::Type::Point, dev::DIRECT_MIS},
                      PunctualCase{"point_bsdf", PunctualLight::Type::Point, dev::DIRECT_BSDF},
                      PunctualCase{"spot_mis", PunctualLight::Type::Spot, dev::DIRECT_MIS},
                      PunctualCase{"spot_light", PunctualLight::Type::Spot, dev::DIRECT_LIGHT},
                      PunctualCase{"directional_mis", PunctualLight::Type::Directional, dev::DIRECT_MIS}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(LightRender, EnvironmentNeeAgreesWithBsdfSampling) {
  // A diffuse sphere on a diffuse floor under the structured map: --direct light and
  // --direct bsdf are independent estimators of the same image.
  Scene s;
  test::add_mesh(s, test::icosphere(glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, 2), diffuse(0.7f));
  test::Mesh floor;
  floor.positions = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  test::add_mesh(s, floor, diffuse(0.5f));
  Camera cam;
  cam.camera_to_world = glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0.894f, -0.447f, 0),
                                  glm::vec4(0, 0.447f, 0.894f, 0), glm::vec4(0, 3.0f, 6.0f, 1));
  cam.yfov = 0.9f;
  cam.aspect = 1.0f;
  s.cameras.push_back(cam);
  const std::string env_file = (fs::temp_directory_path() / ("light-env-" + std::to_string(::getpid()) + ".exr")).string();
  write_image(env_file, test_env_map(64, 32), {});
  auto render = [&](uint32_t direct, uint32_t seed) {
    RenderSettings rs;
    rs.width = rs.height = 16;
    rs.spp = 1024;
    rs.seed = seed;
    rs.max_depth = 3;
    rs.direct = direct;
    rs.env_file = env_file;
    rs.env_rotation = 20.0f;
    Renderer r(test::device_context(), s, rs);
    return r.render().film;
  };
  const FilmResult a = render(dev::DIRECT_LIGHT, 1), b = render(dev::DIRECT_BSDF, 2),
                   c = render(dev::DIRECT_MIS, 3);
  fs::remove(env_file);
  const Image va = variance_of_mean(a.variance, a.samples_per_pixel),
              vb = variance_of_mean(b.variance, b.samples_per_pixel),
              vc = variance_of_mean(c.variance, c.samples_per_pixel);
  for (auto [name, img, var] : {std::tuple{"bsdf", &b, &vb}, std::tuple{"mis", &c, &vc}}) {
    const ZTestResult z = z_test(img->mean, var, a.mean, &va);
    std::cout << "[ cross    ] light vs " << name << ": " << z.passed << "/" << z.tested
              << " pass, max |z| " << z.max_abs_z << "\n";
    EXPECT_GE(z.pass_fraction(), 0.9975) << name;
    for (int ch = 0; ch < 3; ++ch) {
      double m = 0.0, rm = 0.0, sv = 0.0;
      for (size_t i = ch; i < a.mean.rgb.size(); i += 3)
        m += img->mean.rgb[i], rm += a.mean.rgb[i], sv += var->rgb[i] + va.rgb[i];
      EXPECT_LT(std::fabs(m - rm) / std::sqrt(sv), 4.0) << name << " channel " << ch;
    }
  }
  // MIS should not be noisier than the worse of the two.
  double sa = 0.0, sb = 0.0, sc = 0.0;
  for (size_t i = 0; i < va.rgb.size(); ++i) sa += va.rgb[i], sb += vb.rgb[i], sc += vc.rgb[i];
  std::cout << "[ cross    ] mean variance: light " << sa << ", bsdf " << sb << ", mis " << sc << "\n";
  EXPECT_LT(sc, std::max(sa, sb));
}

// --------------------------------------------------------------------------------------
// LightCli

TEST(LightCli, MissingEnvironmentFileExitsTwoNamingIt) {
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  const test::RunResult r = test::run_clpt(
      {scene, "--env", "/tmp/light-no-such-env.hdr", "--spp", "1", "--resolution", "4x4", "-o",
       "/tmp/light-cli-out.exr"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("/tmp/light-no-such-env.hdr"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists("/tmp/light-cli-out.exr"));
}

TEST(LightCli, BadBackgroundIsAUsageError) {
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  for (const char* bad : {"1,2", "1,2,3,4", "a,b,c", "1,-1,1", "1,nan,1"}) {
    const test::RunResult r = test::run_clpt({scene, "--background", bad});
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--background"), std::string::npos) << r.err;
  }
  const test::RunResult both =
      test::run_clpt({scene, "--background", "1,1,1", "--env", "x.hdr"});
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_NE(both.err.find("exclude each other"), std::string::npos) << both.err;
}

TEST(LightCli, RendersWithEnvironmentMap) {
  const std::string dir = (fs::temp_directory_path() / ("light-cli-" + std::to_string(::getpid()))).string();
  fs::create_directories(dir);
  write_image(dir + "/env.exr", test_env_map(), {});
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/furnace.gltf";
  const test::RunResult r = test::run_clpt({scene, "--env", dir + "/env.exr", "--env-scale", "2",
                                            "--env-rotate", "45", "--spp", "2", "--resolution",
                                            "8x8", "-o", dir + "/out.exr", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/out.exr"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clpt::light_test
