// KHR_lights_punctual in the glTF loader (host/scene/gltf_lights.cpp): lights placed by their
// nodes' world transforms (position = translation, direction = -Z), defaults, validation. The
// malformed files are in tests/data/malformed (GltfMalformed.* in gltf_loader_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/gltf_loader.h"
#include "util/error.h"
#include "util/log.h"

namespace clpt::gltf_lights_test {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// One triangle (the malformed corpus's valid base: 3 float positions + 3 u16 indices).
json triangle_doc() {
  // Positions (0,0,0) (1,0,0) (0,1,0) then indices 0 1 2 (+ 2 bytes padding): 44 bytes.
  const std::string b64 =
      "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
  return json{
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers", {{{"uri", "data:application/octet-stream;base64," + b64}, {"byteLength", 44}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
        {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
         {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
  };
}

Scene load_doc(const json& doc, const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("light-gltf-" + name + ".gltf");
  std::ofstream(path) << doc.dump(1);
  log::set_level(log::Level::Quiet);
  Scene s = load_gltf(path);
  fs::remove(path);
  return s;
}

void expect_vec(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(GltfLights, PlacedByNodeWorldTransform) {
  json doc = triangle_doc();
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensionsRequired"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 40.0}, {"name", "bulb"}},
      {{"type", "spot"}, {"intensity", 7.0}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.6}}}},
      {{"type", "directional"}, {"intensity", 3.0}, {"range", 10.0}},
  };
  const double s = std::sqrt(0.5);
  doc["nodes"] = {
      {{"mesh", 0}, {"children", {1, 2}}, {"translation", {0.0, 0.0, 1.0}}},
      // point at parent (0,0,1) + (1,2,3), scaled parent ignored for position only
      {{"translation", {1.0, 2.0, 3.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
      // spot: rotated -90 degrees about x, so -Z points down (-y), and scaled by 5
      {{"rotation", {-s, 0.0, 0.0, s}}, {"scale", {5.0, 5.0, 5.0}},
       {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
      // directional: rotated +90 degrees about y, so -Z points to -x
      {{"rotation", {0.0, s, 0.0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}},
      // the point light again, placed by a second node
      {{"translation", {-4.0, 0.0, 0.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
  };
  doc["scenes"][0]["nodes"] = {0, 3, 4};
  const Scene scene = load_doc(doc, "placed");
  ASSERT_EQ(scene.lights.size(), 4u);  // node traversal order: 1, 2, 3, 4
  const PunctualLight& point = scene.lights[0];
  EXPECT_EQ(point.type, PunctualLight::Type::Point);
  EXPECT_EQ(point.name, "bulb");
  expect_vec(point.position, {1.0f, 2.0f, 4.0f});
  expect_vec(point.color, {1.0f, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(point.intensity, 40.0f);

  const PunctualLight& spot = scene.lights[1];
  EXPECT_EQ(spot.type, PunctualLight::Type::Spot);
  expect_vec(spot.position, {0.0f, 0.0f, 1.0f});
  expect_vec(spot.direction, {0.0f, -1.0f, 0.0f});  // unit despite the node's scale
  EXPECT_FLOAT_EQ(spot.inner_cone, 0.1f);
  EXPECT_FLOAT_EQ(spot.outer_cone, 0.6f);
  expect_vec(spot.color, {1.0f, 1.0f, 1.0f});

  const PunctualLight& sun = scene.lights[2];
  EXPECT_EQ(sun.type, PunctualLight::Type::Directional);
  expect_vec(sun.direction, {-1.0f, 0.0f, 0.0f});
  EXPECT_FLOAT_EQ(sun.intensity, 3.0f);
  EXPECT_FLOAT_EQ(sun.range, 10.0f);

  expect_vec(scene.lights[3].position, {-4.0f, 0.0f, 0.0f});
}

TEST(GltfLights, Defaults) {
  json doc = triangle_doc();
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}, {"spot", json::object()}}};
  doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  doc["scenes"][0]["nodes"] = {0, 1};
  const Scene scene = load_doc(doc, "defaults");
  ASSERT_EQ(scene.lights.size(), 1u);
  const PunctualLight& l = scene.lights[0];
  expect_vec(l.color, {1.0f, 1.0f, 1.0f});
  EXPECT_FLOAT_EQ(l.intensity, 1.0f);
  EXPECT_FLOAT_EQ(l.inner_cone, 0.0f);
  EXPECT_NEAR(l.outer_cone, kPi / 4.0, 1e-6);
  expect_vec(l.position, {0.0f, 0.0f, 0.0f});
  expect_vec(l.direction, {0.0f, 0.0f, -1.0f});  // an untransformed node's -Z
}

TEST(GltfLights, UnreferencedLightsAreNotPlaced) {
  json doc = triangle_doc();
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}}};
  EXPECT_TRUE(load_doc(doc, "unreferenced").lights.empty());
}

TEST(GltfLights, ValidationMessages) {
  struct Case {
    json light;
    const char* message;
  };
  const Case cases[] = {
      {{{"type", "point"}, {"intensity", "bright"}}, "light 0: intensity is not a number"},
      {{{"type", "point"}, {"color", {1.0, -0.5, 1.0}}}, "has a negative color component -0.5"},
      {{{"type", "point"}, {"range", 0.0}}, "has range 0, which is not positive"},
      {{{"type", "spot"}, {"spot", {{"innerConeAngle", -0.1}}}}, "inner -0.1 and outer 0.785398"},
      {{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.3}}}},
       "inner 0.3 and outer 0.3, which do not satisfy 0 <= inner < outer <= pi/2"},
      {{{"type", 3}}, "'type' property is not a string"},  // tinygltf's message
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    json doc = triangle_doc();
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {c.light};
    try {
      load_doc(doc, "invalid");
      ADD_FAILURE() << "loaded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::BadInput);
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
}

// The shared sample assets that require KHR_lights_punctual.
TEST(GltfLights, SharedShadowScenesLoad) {
  const fs::path root = CLPT_SHARED_SCENES_DIR;
  const fs::path dir_file = root / "ShadowsDirectional/glTF/shadows-directional.gltf";
  const fs::path spot_file = root / "ShadowsSpot/glTF/shadows-spot.gltf";
  if (!fs::exists(dir_file) || !fs::exists(spot_file)) GTEST_SKIP() << "shared scenes absent";
  log::set_level(log::Level::Quiet);
  const Scene d = load_gltf(dir_file);
  ASSERT_EQ(d.lights.size(), 1u);
  EXPECT_EQ(d.lights[0].type, PunctualLight::Type::Directional);
  EXPECT_FLOAT_EQ(d.lights[0].intensity, 10.0f);
  // -Z turned by the node's rotation and its parent's (quaternions multiplied out by hand).
  expect_vec(d.lights[0].direction, {-0.5f, -0.5f, 0.70710677f});
  const Scene s = load_gltf(spot_file);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, PunctualLight::Type::Spot);
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 1000.0f);
  EXPECT_NEAR(s.lights[0].inner_cone, 0.353429f, 1e-5f);
  EXPECT_NEAR(s.lights[0].outer_cone, 0.392699f, 1e-5f);
}

}  // namespace
}  // namespace clpt::gltf_lights_test
