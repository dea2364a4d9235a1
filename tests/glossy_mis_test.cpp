// GlossyMis: Veach's multiple-importance-sampling scene (Veach 1997, fig. 9.2): four glossy
// metal plates of increasing roughness under four lights of decreasing size and equal power.
// Light sampling is good for rough plates and large lights, BSDF sampling for smooth plates
// and small lights; each converges to the same image only if the BSDF's sample() and pdf()
// and the lights' illuminate() and pdf() agree with each other. So: direct light only
// (max depth 1), a reference rendered with MIS, and light-only and BSDF-only renders compared
// with it by block means over independent batches (support/block_test.h), since both are
// heavy-tailed here by design. A wrong GGX pdf (in the MIS weight) or a wrong sampled weight
// shows up as a bias of the MIS reference against one of them.
#include <gtest/gtest.h>

#include <cmath>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/block_test.h"
#include "support/device.h"
#include "support/scenes.h"

namespace clpt::glossy_mis_test {
namespace {

constexpr uint32_t kSize = 32;

// A quad of the two triangles (a, b, c) and (a, c, d), counter-clockwise seen from where
// (b - a) x (c - a) points.
test::Mesh quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
  test::Mesh m;
  m.positions = {a, b, c, d};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

Scene veach_plates() {
  Scene scene;
  // Plates: y = 0, facing +y, side by side along x; roughness grows to the right.
  const float roughness[4] = {0.12f, 0.25f, 0.45f, 0.8f};
  for (int i = 0; i < 4; ++i) {
    Material m;
    m.base_color = glm::vec4(0.9f, 0.8f, 0.6f, 1.0f);
    m.metallic = 1.0f;
    m.roughness = roughness[i];
    const float x0 = -4.0f + 2.0f * float(i), x1 = x0 + 1.9f;
    test::add_mesh(scene, quad({x0, 0, 1.5f}, {x1, 0, 1.5f}, {x1, 0, -1.5f}, {x0, 0, -1.5f}), m);
  }
  // Lights: squares behind the plates at height 2, tilted towards them, sizes 1:3:8:20 with
  // radiance falling as 1/area (equal power); double-sided emission, black otherwise.
  const float half[4] = {0.04f, 0.12f, 0.32f, 0.8f};
  const glm::vec3 u(1, 0, 0), v = glm::normalize(glm::vec3(0, 1, 1));  // the light's plane
  for (int i = 0; i < 4; ++i) {
    Material m;
    m.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    m.metallic = 0.0f;
    m.specular = 0.0f;
    m.double_sided = true;
    m.emission = glm::vec3(0.4f / (half[i] * half[i]));
    const glm::vec3 c(-3.0f + 2.0f * float(i), 2.0f, -3.0f);
    const glm::vec3 a = c - half[i] * u - half[i] * v, b = c + half[i] * u - half[i] * v,
                    cc = c + half[i] * u + half[i] * v, d = c - half[i] * u + half[i] * v;
    test::add_mesh(scene, quad(a, b, cc, d), m);
  }
  // The camera sees the lights' mirror images on the plates.
  Camera cam;
  const glm::vec3 eye(0.0f, 2.0f, 4.0f), at(0.0f, 0.0f, 0.0f);
  const glm::vec3 z = glm::normalize(eye - at), x = glm::normalize(glm::cross(glm::vec3(0, 1, 0), z));
  const glm::vec3 y = glm::cross(z, x);
  cam.camera_to_world = glm::mat4(glm::vec4(x, 0), glm::vec4(y, 0), glm::vec4(z, 0), glm::vec4(eye, 1));
  cam.yfov = 1.0f;
  scene.cameras.push_back(cam);
  return scene;
}

RenderSettings settings(uint32_t direct, uint64_t spp, uint32_t seed) {
  RenderSettings s;
  s.width = s.height = kSize;
  s.max_depth = 1;
  s.spp = spp;
  s.seed = seed;
  s.direct = direct;
  return s;
}

const FilmResult& mis_reference() {
  static const FilmResult ref = [] {
    Renderer r(test::device_context(), veach_plates(), settings(dev::DIRECT_MIS, 8192, 99));
    return r.render().film;
  }();
  return ref;
}

void expect_agrees_with_mis(uint32_t direct) {
  const Scene scene = veach_plates();
  const FilmResult& ref = mis_reference();
  std::vector<Image> batches;
  for (uint32_t b = 0; b < 8; ++b) {
    Renderer r(test::device_context(), scene, settings(direct, 512, 1000 + b));
    const FilmResult f = r.render().film;
    ASSERT_EQ(f.dropped_samples, 0u);
    batches.push_back(f.mean);
  }
  const test::BlockTestResult t = test::block_means_test(
      batches, ref.mean, variance_of_mean(ref.variance, ref.samples_per_pixel), 8);
  EXPECT_EQ(t.failed, 0u) << t.summary();
  // The plates must be lit, or the comparison is vacuous.
  double sum = 0.0;
  for (float v : ref.mean.rgb) sum += v;
  EXPECT_GT(sum / double(ref.mean.rgb.size()), 0.01);
}

TEST(GlossyMis, LightSamplingAloneAgreesWithMis) { expect_agrees_with_mis(dev::DIRECT_LIGHT); }
TEST(GlossyMis, BsdfSamplingAloneAgreesWithMis) { expect_agrees_with_mis(dev::DIRECT_BSDF); }

}  // namespace
}  // namespace clpt::glossy_mis_test
