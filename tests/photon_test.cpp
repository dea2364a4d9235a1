// Photon emission (kernels/integrators/photon.cl, host/photon/photon_tracer.*) on PoCL:
//   PhotonPower  in the furnace every photon carries Φ / N (power-proportional light choice,
//                Russian roulette by albedo), and the photons at hit k sum to the power that
//                reaches that hit, (Φ_inner + Φ_outer / 2) ρ^(k-1), z-test with the binomial
//                variance of the count;
//   Caustics     L S+ D flags: none in a diffuse scene; in the Cornell box with a glass block
//                some, all after at least one bounce, and a caustic-only pass keeps only
//                those; a full photon buffer reports what it dropped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

#include "bvh/bvh.h"
#include "photon/photon_tracer.h"
#include "render/scene_buffers.h"
#include "support/device.h"
#include "support/scenes.h"

namespace clpt::photon_test {
namespace {

struct DeviceScene {
  Bvh bvh;
  FlatScene flat;
  std::unique_ptr<SceneBuffers> buffers;
  explicit DeviceScene(const Scene& scene)
      : bvh(build_bvh(scene.positions, scene.triangles)), flat(flatten_scene(scene, bvh)),
        buffers(std::make_unique<SceneBuffers>(test::device_context(), flat)) {}
};

dev::RenderParams photon_params(uint32_t max_depth, uint32_t seed) {
  dev::RenderParams p{};
  p.max_depth = max_depth;
  p.seed = seed;
  p.sampler = dev::SAMPLER_INDEPENDENT;
  return p;
}

uint32_t bounce(const dev::Photon& ph) { return (ph.flags >> PHOTON_BOUNCE_SHIFT) & 0xffu; }

// Emitted power of the scene's emissive triangles, π Le A per emitting side, split into the
// triangles within `radius` of the origin and the rest.
struct ScenePower {
  double inner = 0.0, outer = 0.0;
};
ScenePower scene_power(const Scene& scene, double radius) {
  ScenePower r;
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const Material& m = scene.materials[scene.triangle_materials[i]];
    const glm::dvec3 a(scene.positions[scene.triangles[i].x]), b(scene.positions[scene.triangles[i].y]),
        c(scene.positions[scene.triangles[i].z]);
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    const double power = M_PI * double(m.emission.x) * area * (m.double_sided ? 2.0 : 1.0);
    (glm::length(a) < radius ? r.inner : r.outer) += power;
  }
  return r;
}

// The furnace (support/scenes.h): two double-sided emitting spheres of albedo ρ. Power
// proportional light choice and a cosine direction make every photon path carry Φ / N, and
// Russian roulette by albedo keeps it (ρ / ρ), so every photon's power is Φ / N exactly. The
// outer sphere's outward side (half its power) escapes; everything else lands in one of two
// closed diffuse cavities (between the spheres, inside the inner one), so hit k carries
// (Φ_inner + Φ_outer / 2) ρ^(k-1) in expectation, with a binomial count of photons.
TEST(PhotonPower, PhotonsCarryTheLightsPowerInAFurnace) {
  constexpr float kRho = 0.5f;
  const Scene scene = test::furnace_scene(kRho, 1.0f);
  DeviceScene ds(scene);
  PhotonTracer tracer(test::device_context(), *ds.buffers);
  constexpr uint64_t kPaths = 200000;
  const PhotonSet set = tracer.trace(photon_params(4, 7), kPaths, 0u, kPaths * 4);
  ASSERT_EQ(set.dropped, 0u);
  const ScenePower sp = scene_power(scene, 2.0);
  const double phi = sp.inner + sp.outer;
  double sum[5] = {0, 0, 0, 0, 0};
  double max_dev = 0.0;
  for (const dev::Photon& ph : set.photons) {
    const uint32_t k = bounce(ph);
    ASSERT_GE(k, 1u);
    ASSERT_LE(k, 4u);
    EXPECT_EQ(ph.flags & PHOTON_CAUSTIC, 0u) << "a diffuse scene has no caustic photons";
    sum[k] += ph.power[0];
    max_dev = std::max(max_dev, std::fabs(ph.power[0] * double(kPaths) / phi - 1.0));
  }
  EXPECT_LT(max_dev, 1e-3) << "every photon carries the emitted power / paths";
  const double kept = (sp.inner + 0.5 * sp.outer) / phi;
  for (uint32_t k = 1; k <= 4; ++k) {
    const double q = kept * std::pow(double(kRho), k - 1.0);
    const double expected = phi * q, sigma = phi * std::sqrt(q * (1.0 - q) / double(kPaths));
    const double z = (sum[k] - expected) / sigma;
    EXPECT_LT(std::fabs(z), 4.0) << "hit " << k << ": " << sum[k] << " expected " << expected;
    std::cout << "[ figures  ] hit " << k << ": photon power " << sum[k] << " W, expected "
              << expected << " W (z " << z << ")\n";
  }
  std::cout << "[ figures  ] emitted " << phi << " W; photon power / (Φ/N) within " << max_dev
            << "; " << set.photons.size() << " photons from " << kPaths << " paths\n";
}

TEST(PhotonPower, CausticPhotonsComeOnlyFromDeltaOrGlossyScattering) {
  {
    DeviceScene ds(test::cornell_box());
    PhotonTracer tracer(test::device_context(), *ds.buffers);
    const PhotonSet set = tracer.trace(photon_params(8, 3), 50000, PHOTON_STORE_CAUSTIC_ONLY, 50000 * 8);
    EXPECT_EQ(set.photons.size(), 0u) << "the diffuse Cornell box makes no caustic photons";
  }
  DeviceScene ds(test::cornell_box_glossy_glass());
  PhotonTracer tracer(test::device_context(), *ds.buffers);
  const PhotonSet all = tracer.trace(photon_params(8, 3), 100000, 0u, 100000 * 8);
  const PhotonSet caustic = tracer.trace(photon_params(8, 3), 100000, PHOTON_STORE_CAUSTIC_ONLY, 100000 * 8);
  size_t flagged = 0;
  for (const dev::Photon& ph : all.photons)
    if (ph.flags & PHOTON_CAUSTIC) {
      ++flagged;
      EXPECT_GE(bounce(ph), 2u);
    }
  EXPECT_GT(flagged, 100u) << "the glass block and the glossy metal block focus some photons";
  ASSERT_GT(caustic.photons.size(), 0u);
  for (const dev::Photon& ph : caustic.photons) EXPECT_NE(ph.flags & PHOTON_CAUSTIC, 0u);
  // Same seed, same paths: the caustic pass keeps exactly the flagged photons.
  EXPECT_EQ(caustic.photons.size(), flagged);
  std::cout << "[ figures  ] glass box: " << flagged << " caustic photons of " << all.photons.size()
            << "\n";

  const PhotonSet small = tracer.trace(photon_params(8, 3), 1000, 0u, 10);
  EXPECT_EQ(small.photons.size(), 10u);
  EXPECT_GT(small.dropped, 0u);
}

}  // namespace
}  // namespace clpt::photon_test
