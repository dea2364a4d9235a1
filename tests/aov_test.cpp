// First-hit AOVs (--aov, render/aov.cpp, kernels/integrators/aov.cl; issue 24) against scenes
// whose answers are known: a plane facing the camera (albedo its base colour, or 1 for glass,
// the base colour for a metal; normal +z of unit length; depth the distance along each
// pixel's ray; position on the plane; material index 0), a sphere against nothing (misses:
// index -1, depth +inf; normals along position - centre), and the PFM files oidnDenoise reads.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/pfm.h"
#include "render/aov.h"
#include "render/renderer.h"
#include "support/device.h"
#include "support/parse_options.h"
#include "support/render.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt::aov_test {
namespace {

constexpr uint32_t kSize = 32;
constexpr float kCameraZ = 4.0f, kFov = 0.5f;
constexpr uint32_t kAll = AOV_ALBEDO | AOV_NORMAL | AOV_DEPTH | AOV_POSITION | AOV_MATERIAL_ID;

const Image& layer(const RenderOutput& out, const std::string& name) {
  for (const NamedChannel& l : out.aovs)
    if (l.name == name) return l.image;
  throw std::runtime_error("no AOV layer " + name);
}

RenderOutput render_aovs(const Scene& scene, uint64_t spp) {
  RenderSettings s = test::render_settings("ao", spp, kSize);  // ao: needs no light
  s.aovs = kAll;
  return Renderer(test::device_context(), scene, s).render();
}

Scene plane_scene(const Material& m) {
  Scene scene;
  test::Mesh quad;
  quad.positions = {{-10.0f, -10.0f, 0.0f}, {10.0f, -10.0f, 0.0f}, {10.0f, 10.0f, 0.0f}, {-10.0f, 10.0f, 0.0f}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  test::add_mesh(scene, quad, m);
  test::add_camera_on_z(scene, kCameraZ, kFov);
  return scene;
}

struct PlaneCase {
  const char* name;
  Material material;
  glm::vec3 albedo;
};

std::vector<PlaneCase> plane_cases() {
  Material lambert;
  lambert.base_color = glm::vec4(0.2f, 0.5f, 0.8f, 1.0f);
  lambert.metallic = 0.0f;
  lambert.roughness = 1.0f;
  Material metal = lambert;
  metal.metallic = 1.0f;
  metal.roughness = 0.3f;
  Material glass = test::glass_material(0.0f);
  glass.base_color = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
  return {{"lambert", lambert, {0.2f, 0.5f, 0.8f}},
          {"metal", metal, {0.2f, 0.5f, 0.8f}},
          {"glass", glass, {1.0f, 1.0f, 1.0f}}};  // transmission 1: OIDN's albedo of glass
}

TEST(Aov, PlaneFacingTheCamera) {
  for (const PlaneCase& c : plane_cases()) {
    SCOPED_TRACE(c.name);
    const RenderOutput out = render_aovs(plane_scene(c.material), 16);
    const Image& albedo = layer(out, "Albedo");
    const Image& normal = layer(out, "Normal");
    const Image& depth = layer(out, "Depth");
    const Image& position = layer(out, "Position");
    const Image& index = layer(out, "IndexMA");
    const float footprint = 2.0f * kCameraZ * std::tan(0.5f * kFov) / kSize;  // one pixel on the plane
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const size_t i = (size_t(y) * kSize + x) * 3;
        for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(albedo.rgb[i + ch], c.albedo[ch], 1e-5f) << x << "," << y;
        const glm::vec3 n(normal.rgb[i], normal.rgb[i + 1], normal.rgb[i + 2]);
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << x << "," << y;
        ASSERT_GT(n.z, 0.99999f) << "the plane's normal, towards the camera";
        // The pixel centre's ray, and the distance along it to z = 0. The 16 samples jitter over
        // the pixel, so their means scatter about the centre's values: a position by
        // footprint / sqrt(12 x 16) = 0.072 footprints, a depth by under 3e-4 of itself.
        const glm::vec3 d = test::pixel_centre_direction(x, y, kSize, kFov);
        const float t = kCameraZ / -d.z;
        ASSERT_NEAR(depth.rgb[i], t * glm::length(d), 2e-3f * t) << x << "," << y;
        const glm::vec3 p(position.rgb[i], position.rgb[i + 1], position.rgb[i + 2]);
        const glm::vec3 expected = glm::vec3(0.0f, 0.0f, kCameraZ) + t * d;
        ASSERT_NEAR(p.z, 0.0f, 1e-4f);
        ASSERT_NEAR(p.x, expected.x, 0.4f * footprint) << x << "," << y;
        ASSERT_NEAR(p.y, expected.y, 0.4f * footprint) << x << "," << y;
        ASSERT_EQ(index.rgb[i], 0.0f);
      }
  }
}

TEST(Aov, SphereAgainstNothing) {
  Scene scene;
  Material m;
  m.base_color = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
  m.metallic = 0.0f;
  test::add_mesh(scene, test::uv_sphere({0.0f, 0.0f, 0.0f}, 0.6f, 64, 32), m);
  test::add_camera_on_z(scene, kCameraZ, kFov);
  const RenderOutput out = render_aovs(scene, 16);
  const Image& normal = layer(out, "Normal");
  const Image& depth = layer(out, "Depth");
  const Image& position = layer(out, "Position");
  const Image& index = layer(out, "IndexMA");
  const Image& albedo = layer(out, "Albedo");
  size_t on = 0, off = 0;
  for (size_t px = 0; px < size_t(kSize) * kSize; ++px) {
    const size_t i = px * 3;
    const glm::vec3 p(position.rgb[i], position.rgb[i + 1], position.rgb[i + 2]);
    const glm::vec3 n(normal.rgb[i], normal.rgb[i + 1], normal.rgb[i + 2]);
    if (std::isinf(depth.rgb[i])) {  // no sample hit: nothing to average
      ++off;
      EXPECT_EQ(index.rgb[i], -1.0f);
      EXPECT_EQ(albedo.rgb[i], 0.0f);
      EXPECT_EQ(glm::length(n), 0.0f);
      continue;
    }
    EXPECT_NEAR(glm::length(p), 0.6f, 0.01f) << "on the sphere (a tessellated one)";
    if (albedo.rgb[i] < 0.6f - 1e-5f) continue;  // an edge pixel: some samples missed
    ++on;
    EXPECT_EQ(index.rgb[i], 0.0f);
    EXPECT_NEAR(depth.rgb[i], glm::length(p - glm::vec3(0.0f, 0.0f, kCameraZ)), 0.02f);
    // Averaged shading normals of a smooth sphere point along the averaged position.
    EXPECT_GT(glm::dot(glm::normalize(n), glm::normalize(p)), 0.995f) << px;
    EXPECT_GT(glm::length(n), 0.98f);
  }
  EXPECT_GT(on, 100u);
  EXPECT_GT(off, 100u);
}

// The PFM writer against OpenImageIO's reader: the same pixels, rows in the right order.
TEST(Aov, PfmIsWhatOpenImageIoReads) {
  Image image(5, 3);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i) * 0.25f - 3.0f;
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("clpt-pfm-" + std::to_string(::getpid()) + ".pfm");
  write_pfm(file, image);
  auto in = OIIO::ImageInput::open(file.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  ASSERT_EQ(in->spec().width, 5);
  ASSERT_EQ(in->spec().height, 3);
  ASSERT_EQ(in->spec().nchannels, 3);
  std::vector<float> back(image.rgb.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, back.data()));
  in.reset();
  std::filesystem::remove(file);
  EXPECT_EQ(back, image.rgb);
}

TEST(AovOptions, NamesAreChecked) {
  EXPECT_EQ(test::parse_error({"s.gltf", "--aov", "albedo,normal,depth,position,material-id,variance"}),
            ExitCode::Ok);
  EXPECT_EQ(test::parse_error({"s.gltf", "--aov", "albedo", "--aov-pfm"}), ExitCode::Ok);
  EXPECT_EQ(test::parse_error({"s.gltf", "--aov", "shadow"}), ExitCode::Usage);
  EXPECT_EQ(test::parse_error({"s.gltf", "--aov", "albedo,albedo"}), ExitCode::Usage);
  // variance in --aov is --variance, with its limits.
  EXPECT_EQ(test::parse_error({"s.gltf", "--integrator", "bdpt", "--aov", "variance"}), ExitCode::Usage);
  EXPECT_EQ(test::parse_error({"s.gltf", "--integrator", "bdpt", "--aov", "albedo,normal"}), ExitCode::Ok);
  EXPECT_EQ(test::parse_error({"s.gltf", "--integrator", "bdpt", "--bdpt-mosaic", "--aov", "albedo"}), ExitCode::Usage);
}

}  // namespace
}  // namespace clpt::aov_test
