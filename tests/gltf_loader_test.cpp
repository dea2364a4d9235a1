// Tests of the glTF loader (host/scene/gltf_loader.*) and of scene.cpp.
//
//  GltfConformance: the real sample assets under CLPT_SHARED_SCENES_DIR (skipped when absent).
//  GltfMalformed:   tests/data/malformed, one broken file per case (see its README.md).
//  GltfLoader:      tests/data/valid, tiny files with exact expected world positions.
//  GltfFuzz:        byte mutations and truncations of valid files must never crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "io/png_codec.h"
#include "scene/gltf_loader.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/log.h"

namespace fs = std::filesystem;

namespace gltf_loader_test {
namespace {

const fs::path kShared = CLPT_SHARED_SCENES_DIR;
const fs::path kMalformed = fs::path(CLPT_TEST_DATA_DIR) / "malformed";
const fs::path kValid = fs::path(CLPT_TEST_DATA_DIR) / "valid";

// Skips the test when the shared scenes (or one asset) are not there.
#define REQUIRE_SHARED(rel)                                                                   \
  do {                                                                                        \
    if (!fs::exists(kShared / (rel)))                                                         \
      GTEST_SKIP() << "shared glTF scene " << (kShared / (rel))                               \
                   << " not found (CLPT_SHARED_SCENES_DIR); the conformance tests need it";   \
  } while (0)

struct LoadResult {
  bool ok = false;
  clpt::Scene scene;
  clpt::ExitCode code = clpt::ExitCode::Ok;
  std::string message;
  bool other_exception = false;
};

LoadResult try_load(const fs::path& path) {
  LoadResult r;
  try {
    r.scene = clpt::load_gltf(path);
    r.ok = true;
  } catch (const clpt::Error& e) {
    r.code = e.code();
    r.message = e.what();
  } catch (const std::exception& e) {
    r.other_exception = true;
    r.message = e.what();
  }
  return r;
}

// The message of the BadInput error that loading `path` must give.
std::string load_error(const fs::path& path) {
  LoadResult r = try_load(path);
  EXPECT_FALSE(r.ok) << path << " loaded, but it should not";
  EXPECT_FALSE(r.other_exception) << path << " threw a non-clpt exception: " << r.message;
  EXPECT_EQ(r.code, clpt::ExitCode::BadInput) << r.message;
  EXPECT_NE(r.message.find(path.filename().string()), std::string::npos)
      << "message does not name the file: " << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos) << "message is not one line: " << r.message;
  return r.message;
}

clpt::Scene load_ok(const fs::path& path) {
  LoadResult r = try_load(path);
  EXPECT_TRUE(r.ok) << r.message;
  return r.scene;
}

std::vector<unsigned char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

glm::vec3 geometric_normal(const clpt::Scene& s, size_t t) {
  const glm::uvec3 tri = s.triangles[t];
  const glm::vec3 a = s.positions[tri.x], b = s.positions[tri.y], c = s.positions[tri.z];
  return glm::cross(b - a, c - a);
}

void expect_near(const glm::vec3& got, const glm::vec3& want, float eps = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, eps) << "x";
  EXPECT_NEAR(got.y, want.y, eps) << "y";
  EXPECT_NEAR(got.z, want.z, eps) << "z";
}

// Every scene that loads must be internally consistent.
void expect_consistent(const clpt::Scene& s, const std::string& name) {
  ASSERT_EQ(s.normals.size(), s.positions.size()) << name;
  ASSERT_EQ(s.uvs.size(), s.positions.size()) << name;
  ASSERT_EQ(s.triangle_materials.size(), s.triangles.size()) << name;
  ASSERT_FALSE(s.materials.empty()) << name;
  ASSERT_FALSE(s.triangles.empty()) << name;
  for (const glm::uvec3& t : s.triangles) {
    ASSERT_LT(t.x, s.positions.size()) << name;
    ASSERT_LT(t.y, s.positions.size()) << name;
    ASSERT_LT(t.z, s.positions.size()) << name;
  }
  for (uint32_t m : s.triangle_materials) ASSERT_LT(m, s.materials.size()) << name;
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const glm::vec3& p = s.positions[i];
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << name;
    const glm::vec3& n = s.normals[i];
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << name;
    const float len = glm::length(n);
    ASSERT_TRUE(len == 0.0f || std::fabs(len - 1.0f) < 1e-3f) << name << " normal length " << len;
    ASSERT_TRUE(std::isfinite(s.uvs[i].x) && std::isfinite(s.uvs[i].y)) << name;
  }
  for (const clpt::Camera& c : s.cameras) {
    const glm::mat3 r(c.camera_to_world);
    EXPECT_NEAR(glm::determinant(r), 1.0f, 1e-4f) << name << " camera " << c.name;
    EXPECT_NEAR(glm::dot(r[0], r[1]), 0.0f, 1e-4f) << name;
    EXPECT_NEAR(glm::dot(r[1], r[2]), 0.0f, 1e-4f) << name;
    EXPECT_NEAR(glm::length(r[0]), 1.0f, 1e-4f) << name;
  }
}

// ------------------------------------------------------------------------------------------
// Conformance: the real sample assets

TEST(GltfConformance, EveryFileLoadsOrFailsCleanly) {
  if (!fs::is_directory(kShared))
    GTEST_SKIP() << "shared glTF scenes not found at " << kShared << " (CLPT_SHARED_SCENES_DIR)";
  clpt::log::set_level(clpt::log::Level::Quiet);
  // The file clpt must refuse: Empty has nothing to render. Every other file must load (Draco
  // included: tests/compressed_geometry_test.cpp compares it with its uncompressed twin).
  const std::set<std::string> expected_refusals = {"Empty/Empty.gltf"};
  std::set<std::string> refusals;
  size_t loaded = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kShared)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
    SCOPED_TRACE(entry.path().string());
    LoadResult r = try_load(entry.path());
    EXPECT_FALSE(r.other_exception) << "non-clpt exception: " << r.message;
    if (r.ok) {
      ++loaded;
      expect_consistent(r.scene, entry.path().string());
    } else {
      const std::string rel = entry.path().lexically_relative(kShared).generic_string();
      refusals.insert(rel);
      EXPECT_TRUE(expected_refusals.count(rel)) << "refused: " << r.message;
      EXPECT_EQ(r.code, clpt::ExitCode::BadInput) << r.message;
      EXPECT_FALSE(r.message.empty());
      EXPECT_NE(r.message.find(entry.path().filename().string()), std::string::npos) << r.message;
    }
  }
  EXPECT_GE(loaded, 25u);
  EXPECT_EQ(refusals, expected_refusals);
}

TEST(GltfConformance, TriangleCounts) {
  if (!fs::is_directory(kShared))
    GTEST_SKIP() << "shared glTF scenes not found at " << kShared << " (CLPT_SHARED_SCENES_DIR)";
  // Counted from the accessors (TRIANGLES n/3, STRIP/FAN n-2, per node and per instance).
  const std::map<std::string, size_t> expected = {
      {"CornellBox/CornellBox.glb", 36},
      {"Triangle/glTF/Triangle.gltf", 1},
      {"Triangle/glTF-Embedded/Triangle.gltf", 1},
      {"TriangleWithoutIndices/glTF/TriangleWithoutIndices.gltf", 1},
      {"MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf", 16},
      {"Cameras/glTF/Cameras.gltf", 2},
      {"SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf", 12},
      {"OrientationTest/glTF-Binary/OrientationTest.glb", 524},
      {"BoxWithSpaces/glTF/Box With Spaces.gltf", 12},
      {"Box/glTF/Box.gltf", 12},
      {"NoScene/NoScene.gltf", 12},
      {"NegativeScaleTest/glTF-Binary/NegativeScaleTest.glb", 7724},
      {"SimpleInstancing/glTF-Binary/SimpleInstancing.glb", 1500},
      {"EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb", 90},
      {"TextureCoordinateTest/glTF-Binary/TextureCoordinateTest.glb", 10},
      {"AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb", 61},
      {"TransmissionTest/glTF-Binary/TransmissionTest.glb", 128775},
  };
  clpt::log::set_level(clpt::log::Level::Quiet);
  for (const auto& [rel, count] : expected) {
    if (!fs::exists(kShared / rel)) {
      ADD_FAILURE() << "missing shared asset " << rel;
      continue;
    }
    clpt::Scene s = load_ok(kShared / rel);
    EXPECT_EQ(s.triangles.size(), count) << rel;
  }
}

TEST(GltfConformance, CornellBoxLight) {
  REQUIRE_SHARED("CornellBox/CornellBox.glb");
  clpt::Scene s = load_ok(kShared / "CornellBox/CornellBox.glb");
  ASSERT_EQ(s.triangles.size(), 36u);
  // The light is one quad: 2 triangles of material "Emitter_Light_temp", emissiveFactor 1 x
  // KHR_materials_emissive_strength 100.
  EXPECT_EQ(s.emissive_triangle_count(), 2u);
  ASSERT_EQ(s.materials.size(), 5u);  // all primitives have materials: no default added
  const clpt::Material& light = s.materials[0];
  EXPECT_EQ(light.name, "Emitter_Light_temp");
  expect_near(light.emission, glm::vec3(100.0f));
  EXPECT_TRUE(light.double_sided);
  EXPECT_FLOAT_EQ(light.metallic, 0.0f);
  EXPECT_FLOAT_EQ(light.roughness, 0.5f);
  EXPECT_NEAR(light.base_color.x, 0.8f, 1e-6f);
  for (size_t i = 1; i < s.materials.size(); ++i) EXPECT_EQ(s.materials[i].emission, glm::vec3(0.0f));
  EXPECT_TRUE(s.cameras.empty());
  // Units are millimetres: the box spans about 556 x 549 x 559.
  const clpt::Bounds b = s.bounds();
  EXPECT_NEAR(b.extent().x, 556.0f, 1.0f);
  EXPECT_NEAR(b.extent().y, 548.8f, 1.0f);
  EXPECT_NEAR(b.extent().z, 559.2f, 1.0f);
}

TEST(GltfConformance, EmissiveStrength) {
  REQUIRE_SHARED("EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb");
  clpt::Scene s = load_ok(kShared / "EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb");
  std::map<std::string, float> strength = {{"Emit1", 1}, {"Emit2", 2}, {"Emit4", 4}, {"Emit8", 8}, {"Emit16", 16}};
  size_t seen = 0;
  for (const clpt::Material& m : s.materials) {
    auto it = strength.find(m.name);
    if (it == strength.end()) continue;
    ++seen;
    expect_near(m.emission, glm::vec3(0.1f, 0.5f, 0.9f) * it->second, 1e-5f);
  }
  EXPECT_EQ(seen, 5u);
}

// Box/glTF-Draco against Box/glTF: tests/compressed_geometry_test.cpp.

// KHR_lights_punctual files (ShadowsDirectional, ShadowsSpot) load: tests/gltf_lights_test.cpp.

TEST(GltfConformance, EmptyHasNothingToRender) {
  REQUIRE_SHARED("Empty/Empty.gltf");
  std::string msg = load_error(kShared / "Empty/Empty.gltf");
  EXPECT_NE(msg.find("nothing to render"), std::string::npos) << msg;
}

TEST(GltfConformance, TriangleGetsDefaultMaterial) {
  for (const char* rel : {"Triangle/glTF/Triangle.gltf", "Triangle/glTF-Embedded/Triangle.gltf",
                          "TriangleWithoutIndices/glTF/TriangleWithoutIndices.gltf"}) {
    REQUIRE_SHARED(rel);
    clpt::Scene s = load_ok(kShared / rel);
    ASSERT_EQ(s.triangles.size(), 1u) << rel;
    ASSERT_EQ(s.materials.size(), 1u) << rel;
    EXPECT_EQ(s.materials[0].base_color, glm::vec4(1.0f));
    EXPECT_EQ(s.materials[0].metallic, 1.0f);
    EXPECT_EQ(s.materials[0].roughness, 1.0f);
    EXPECT_EQ(s.materials[0].emission, glm::vec3(0.0f));
    EXPECT_EQ(s.emissive_triangle_count(), 0u);
    for (const glm::vec3& n : s.normals) EXPECT_EQ(n, glm::vec3(0.0f)) << "no NORMAL: zero normals";
    // The triangle (0,0,0) (1,0,0) (0,1,0) faces +Z.
    EXPECT_GT(geometric_normal(s, 0).z, 0.0f) << rel;
  }
}

TEST(GltfConformance, MeshPrimitiveModesKeepsTrianglesOnly) {
  REQUIRE_SHARED("MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf");
  clpt::Scene s = load_ok(kShared / "MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf");
  // TRIANGLES 18 indices -> 6, TRIANGLE_STRIP 6 -> 4, TRIANGLE_FAN 8 -> 6. The four point and
  // line primitives are skipped.
  EXPECT_EQ(s.triangles.size(), 16u);
  // All three triangle meshes face the viewer (+Z) in the reference screenshot.
  for (size_t t = 0; t < s.triangles.size(); ++t) EXPECT_GT(geometric_normal(s, t).z, 0.0f) << "triangle " << t;
}

TEST(GltfConformance, Cameras) {
  REQUIRE_SHARED("Cameras/glTF/Cameras.gltf");
  clpt::Scene s = load_ok(kShared / "Cameras/glTF/Cameras.gltf");
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.cameras[0].type, clpt::Camera::Type::Perspective);
  EXPECT_NEAR(s.cameras[0].yfov, 0.7f, 1e-6f);
  EXPECT_NEAR(s.cameras[0].aspect, 1.0f, 1e-6f);
  EXPECT_EQ(s.cameras[1].type, clpt::Camera::Type::Orthographic);
  EXPECT_NEAR(s.cameras[1].xmag, 1.0f, 1e-6f);
  EXPECT_NEAR(s.cameras[1].ymag, 1.0f, 1e-6f);
  for (const clpt::Camera& c : s.cameras) {
    expect_near(glm::vec3(c.camera_to_world[3]), glm::vec3(0.5f, 0.5f, 3.0f));
    expect_near(glm::vec3(c.camera_to_world[2]), glm::vec3(0.0f, 0.0f, 1.0f));  // looks down -Z
  }
}

TEST(GltfConformance, SparseAccessorOverridesPositions) {
  const std::string rel = "SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf";
  REQUIRE_SHARED(rel);
  // Work out the expected positions from the file itself: the base accessor values, then the
  // sparse (index, value) pairs on top.
  const fs::path gltf = kShared / rel;
  nlohmann::json j = nlohmann::json::parse(read_bytes(gltf));
  const std::vector<unsigned char> bin = read_bytes(gltf.parent_path() / j["buffers"][0]["uri"].get<std::string>());
  const auto& acc = j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  ASSERT_TRUE(acc.contains("sparse"));
  auto view_offset = [&](int view) { return j["bufferViews"][view].value("byteOffset", 0); };
  const size_t count = acc["count"];
  std::vector<glm::vec3> base(count);
  std::memcpy(base.data(), bin.data() + view_offset(acc["bufferView"]) + acc.value("byteOffset", 0), count * 12);
  const auto& sp = acc["sparse"];
  ASSERT_EQ(sp["indices"]["componentType"].get<int>(), 5123);
  const size_t n = sp["count"];
  std::vector<uint16_t> idx(n);
  std::vector<glm::vec3> val(n);
  std::memcpy(idx.data(), bin.data() + view_offset(sp["indices"]["bufferView"]) + sp["indices"].value("byteOffset", 0), n * 2);
  std::memcpy(val.data(), bin.data() + view_offset(sp["values"]["bufferView"]) + sp["values"].value("byteOffset", 0), n * 12);
  std::vector<glm::vec3> expected = base;
  for (size_t k = 0; k < n; ++k) expected[idx[k]] = val[k];

  clpt::Scene s = load_ok(gltf);
  ASSERT_EQ(s.positions.size(), count);  // one node, identity transform
  size_t changed = 0;
  for (size_t i = 0; i < count; ++i) {
    SCOPED_TRACE("vertex " + std::to_string(i));
    expect_near(s.positions[i], expected[i]);
    if (s.positions[i] != base[i]) ++changed;
  }
  EXPECT_EQ(changed, n) << "every sparse value differs from its base value in this asset";
}

TEST(GltfConformance, NegativeScaleKeepsWindingAndNormalsConsistent) {
  const std::string rel = "NegativeScaleTest/glTF-Binary/NegativeScaleTest.glb";
  REQUIRE_SHARED(rel);
  clpt::Scene s = load_ok(kShared / rel);
  size_t agree = 0, considered = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const glm::vec3 ng = geometric_normal(s, t);
    const glm::uvec3 tri = s.triangles[t];
    const glm::vec3 ns = s.normals[tri.x] + s.normals[tri.y] + s.normals[tri.z];
    if (glm::length(ng) < 1e-12f || glm::length(ns) < 1e-6f) continue;
    ++considered;
    if (glm::dot(ng, ns) > 0.0f) ++agree;
  }
  ASSERT_GT(considered, 7000u);
  EXPECT_GT(double(agree) / double(considered), 0.95) << agree << " of " << considered;
}

TEST(GltfConformance, OrientationTestMixedIndices) {
  REQUIRE_SHARED("OrientationTest/glTF-Binary/OrientationTest.glb");
  clpt::Scene s = load_ok(kShared / "OrientationTest/glTF-Binary/OrientationTest.glb");
  EXPECT_EQ(s.triangles.size(), 524u);
  expect_consistent(s, "OrientationTest");
}

TEST(GltfConformance, UrisWithSpaces) {
  REQUIRE_SHARED("BoxWithSpaces/glTF/Box With Spaces.gltf");
  clpt::Scene s = load_ok(kShared / "BoxWithSpaces/glTF/Box With Spaces.gltf");
  EXPECT_EQ(s.triangles.size(), 12u);
}

TEST(GltfConformance, InstancingIsFlattened) {
  REQUIRE_SHARED("SimpleInstancing/glTF-Binary/SimpleInstancing.glb");
  clpt::Scene s = load_ok(kShared / "SimpleInstancing/glTF-Binary/SimpleInstancing.glb");
  EXPECT_EQ(s.triangles.size(), 125u * 12u);
  EXPECT_GT(s.bounds().extent().x, 10.0f);  // spread out, not 125 copies in one place
}

// ------------------------------------------------------------------------------------------
// Malformed corpus (tests/data/malformed, listed in its README.md)

struct MalformedCase {
  const char* file;
  const char* message;  // must appear in the error message
};

const MalformedCase kMalformedCases[] = {
    {"accessor_overrun.gltf",
     "accessor 0 (POSITION of mesh 0 primitive 0) reads bytes 0..48 past the end of bufferView 0 (36 bytes)"},
    {"bufferview_overrun.gltf", "bufferView 1 reads bytes 36..136 past the end of buffer 0 (44 bytes)"},
    {"huge_count.gltf", "has count 4611686018427387905, more than the limit"},
    {"huge_byte_offset.gltf", "reads bytes 9223372036854775808..9223372036854775844 past the end of bufferView 0"},
    {"stride_too_small.gltf", "has elements of 12 bytes, but bufferView 0 has byteStride 4"},
    {"wrong_accessor_type.gltf", "has type VEC2, expected VEC3"},
    {"float_indices.gltf", "(indices of mesh 0 primitive 0) has component type FLOAT"},
    {"index_out_of_range.gltf", "index 7 (entry 2 of accessor 1) is not less than the vertex count 3"},
    {"nan_position.gltf", "mesh 0 primitive 0: POSITION 1 is not finite"},
    {"invalid_accessor_index.gltf", "refers to accessor 9, which does not exist"},
    {"missing_position.gltf", "mesh 0 primitive 0 has no POSITION attribute"},
    {"bad_mode.gltf", "has mode 9, which is not a triangle mode"},
    {"sparse_index_out_of_range.gltf", "sparse index 5 (entry 0) is not less than its count 3"},
    {"uri_parent_escape.gltf", "has '..' components that leave the scene's folder"},
    {"uri_percent_escape.gltf", "has '..' components that leave the scene's folder"},
    {"uri_absolute.gltf", "'/etc/passwd' is an absolute path"},
    {"uri_http.gltf", "uses the URI scheme 'http:'"},
    {"uri_file_scheme.gltf", "uses the URI scheme 'file:'"},
    {"missing_bin.gltf", "file 'missing.bin' not found"},
    {"bin_size_mismatch.gltf", "File size mismatch"},
    {"basisu_required.gltf", "requires extension KHR_texture_basisu, which clpt does not support (KTX2 / Basis Universal"},
    {"quantized_without_extension.gltf", "integer attributes need KHR_mesh_quantization in extensionsUsed"},
    {"meshopt_bad_mode.gltf", "EXT_meshopt_compression has mode 'STRIPS'; expected ATTRIBUTES, TRIANGLES or INDICES"},
    {"meshopt_bad_stride.gltf", "has byteStride 6; ATTRIBUTES needs a multiple of 4 up to 256"},
    {"meshopt_past_buffer.gltf", "EXT_meshopt_compression reads bytes 44..4140 past the end of buffer 0"},
    {"meshopt_count_over_limit.gltf", "EXT_meshopt_compression has count 2147483647, more than the limit of 1073741824"},
    {"meshopt_garbage.gltf", "meshoptimizer cannot decode its 16 bytes into 3 elements of 12 bytes"},
    {"draco_garbage.gltf", "KHR_draco_mesh_compression: Draco cannot decode bufferView 2 (32 bytes)"},
    // KHR_lights_punctual (host/scene/gltf_lights.cpp; valid files in tests/gltf_lights_test.cpp)
    {"lights_bad_type.gltf", "KHR_lights_punctual light 0 has type 'area', expected point, spot or directional"},
    {"lights_negative_intensity.gltf", "KHR_lights_punctual light 0 has a negative intensity -1"},
    {"lights_bad_color.gltf", "KHR_lights_punctual light 0 has a color that is not an array of 3 numbers"},
    {"lights_cone_order.gltf", "which do not satisfy 0 <= inner < outer <= pi/2"},
    {"lights_cone_too_wide.gltf", "has cone angles inner 0 and outer 2, which do not satisfy"},
    {"lights_spot_without_cone.gltf", "Spot light description not found"},
    {"lights_index_out_of_range.gltf", "node 1 refers to light 3, which does not exist (the file has 1)"},
    {"lights_node_without_index.gltf", "node 1 has a KHR_lights_punctual extension without a light index"},
    {"lights_power_overflow.gltf", "color x intensity (1e+60) is too large for a float"},
    {"camera_past_float_range.gltf", "node 1 has a world transform too large for a float (1e+39)"},
    {"index_past_32_bits.gltf", "nodes[0].mesh is 4294967296, which is not an index (an integer from 0 to 2147483647)"},
    {"negative_default_scene.gltf", "scene is -5, which is not an index"},
    {"empty_scene.gltf", "nothing to render"},
    {"no_scenes_no_nodes.gltf", "nothing to render"},
    {"default_scene_out_of_range.gltf", "the default scene 4 does not exist"},
    {"invalid_node_index.gltf", "refers to node 5, which does not exist"},
    {"invalid_mesh_index.gltf", "refers to mesh 3, which does not exist"},
    {"node_cycle.gltf", "the node graph has a cycle"},
    {"node_self_child.gltf", "the node graph has a cycle"},
    {"deep_hierarchy.gltf", "the node hierarchy is deeper than 1024 levels"},
    {"zero_quaternion.gltf", "has a rotation that is not a unit quaternion"},
    {"matrix_wrong_size.gltf", "has a matrix of 6 numbers, expected 16"},
    {"invalid_json.gltf", "invalid JSON"},
    {"truncated.gltf", "invalid JSON"},
    {"zero_bytes.gltf", "the file is empty"},
    {"not_an_object.gltf", "the JSON root is not an object"},
    {"gltf_version_1.gltf", "glTF version '1.0' is not supported"},
    {"deep_nesting.gltf", "JSON nesting is deeper than 256 levels"},
    {"glb_length_lie.glb", "GLB header says the file is 660 bytes, but it is 560 bytes"},
    {"glb_length_short.glb", "GLB header says the file is 552 bytes, but it is 560 bytes"},
    {"glb_truncated.glb", "GLB header says the file is 560 bytes, but it is 540 bytes"},
    {"glb_header_only.glb", "truncated GLB"},
    {"glb_version_1.glb", "GLB version 1 is not supported"},
    {"glb_bad_chunk_type.glb", "GLB chunk 0 has type 0x4F4E534A, expected JSON"},
    {"glb_chunk_length_overrun.glb", "GLB JSON chunk (4294967280 bytes at offset 20) runs past the end of the file"},
    {"glb_bad_bin_chunk.glb", "GLB chunk 1 has type 0x005A5958, expected BIN"},
    {"glb_bin_too_short.glb", "Invalid `byteLength'"},
    {"texture_bad_image.gltf", "image 0 (used by material 0 baseColorTexture): truncated PNG: chunk 0"},
    {"texture_too_large.gltf", "the image is 16385x1, larger than the limit of 16384 per side"},
    {"texture_index_out_of_range.gltf",
     "material 0 baseColorTexture refers to texture 5, which does not exist (the file has 1)"},
    {"texture_texcoord_7.gltf", "material 0 baseColorTexture uses texCoord 7; clpt reads TEXCOORD_0 and TEXCOORD_1 only"},
    {"sheen_bad_color.gltf", "material 0 KHR_materials_sheen sheenColorFactor is not an array of 3 numbers"},
    {"anisotropy_bad_rotation.gltf", "material 0 KHR_materials_anisotropy anisotropyRotation is not a number"},
    {"dispersion_not_a_number.gltf", "material 0 KHR_materials_dispersion dispersion is not a number"},
    {"clearcoat_normal_bad_scale.gltf",
     "material 0 KHR_materials_clearcoat clearcoatNormalTexture scale is not a number"},
    {"texture_bufferview_overrun.glb", "bufferView 2 reads bytes 40..4136 past the end of buffer 0 (44 bytes)"},
};

TEST(GltfMalformed, EveryCaseGivesItsError) {
  clpt::log::set_level(clpt::log::Level::Quiet);
  for (const MalformedCase& c : kMalformedCases) {
    SCOPED_TRACE(c.file);
    const fs::path path = kMalformed / c.file;
    ASSERT_TRUE(fs::exists(path)) << path << " is missing; run tests/data/malformed/make_malformed.py";
    const std::string msg = load_error(path);
    EXPECT_EQ(msg.rfind(path.string() + ": ", 0), 0u) << "message does not start with the path: " << msg;
    EXPECT_NE(msg.find(c.message), std::string::npos) << "expected \"" << c.message << "\" in: " << msg;
  }
}

TEST(GltfMalformed, TableCoversCorpusAndReadme) {
  std::vector<std::string> table;
  for (const MalformedCase& c : kMalformedCases) table.push_back(c.file);
  std::ifstream readme_in(kMalformed / "README.md");
  const std::string readme((std::istreambuf_iterator<char>(readme_in)), {});
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(kMalformed)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    ++files;
    const std::string name = entry.path().filename().string();
    EXPECT_NE(std::find(table.begin(), table.end(), name), table.end()) << name << " is not in the test table";
    EXPECT_NE(readme.find("`" + name + "`"), std::string::npos) << name << " is not in README.md";
  }
  EXPECT_EQ(files, table.size());
}

TEST(GltfMalformed, MissingFileAndDirectory) {
  std::string msg = load_error(kMalformed / "does_not_exist.gltf");
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;
  LoadResult r = try_load(kValid);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.code, clpt::ExitCode::BadInput);
  EXPECT_NE(r.message.find("is a directory"), std::string::npos) << r.message;
}

// ------------------------------------------------------------------------------------------
// Small valid files (tests/data/valid) with exact expectations

TEST(GltfLoader, QuadWithU8IndicesUnderTrsHierarchy) {
  clpt::Scene s = load_ok(kValid / "quad_trs_u8.gltf");
  expect_consistent(s, "quad_trs_u8");
  // world = T(10,0,0) S(2) * T(0,1,0) Rz(90 degrees); local quad (0,0,0) (1,0,0) (1,1,0) (0,1,0).
  ASSERT_EQ(s.positions.size(), 4u);
  expect_near(s.positions[0], {10, 2, 0});
  expect_near(s.positions[1], {10, 4, 0});
  expect_near(s.positions[2], {8, 4, 0});
  expect_near(s.positions[3], {8, 2, 0});
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(s.triangles[1], glm::uvec3(0, 2, 3));
  for (size_t t = 0; t < 2; ++t) EXPECT_GT(geometric_normal(s, t).z, 0.0f);  // still counter-clockwise
  for (const glm::vec3& n : s.normals) expect_near(n, {0, 0, 1});
  // Normalized u8 UVs through a bufferView with byteStride 4.
  EXPECT_EQ(s.uvs[0], glm::vec2(0, 0));
  EXPECT_EQ(s.uvs[1], glm::vec2(1, 0));
  EXPECT_EQ(s.uvs[2], glm::vec2(1, 1));
  EXPECT_EQ(s.uvs[3], glm::vec2(0, 1));
  // Material: factors, emission = emissiveFactor x emissiveStrength 3.
  ASSERT_EQ(s.materials.size(), 1u);
  const clpt::Material& m = s.materials[0];
  EXPECT_EQ(m.name, "Lamp");
  EXPECT_NEAR(m.base_color.x, 0.2f, 1e-6f);
  EXPECT_NEAR(m.base_color.y, 0.4f, 1e-6f);
  EXPECT_NEAR(m.base_color.z, 0.6f, 1e-6f);
  EXPECT_NEAR(m.metallic, 0.25f, 1e-6f);
  EXPECT_NEAR(m.roughness, 0.75f, 1e-6f);
  expect_near(m.emission, {3.0f, 1.5f, 0.0f});
  EXPECT_TRUE(m.double_sided);
  EXPECT_EQ(s.emissive_triangle_count(), 2u);
  // Camera under the scaled parent: position T(10,0,0) S(2) (0,0,5) = (10,0,10), scale removed.
  ASSERT_EQ(s.cameras.size(), 1u);
  const clpt::Camera& c = s.cameras[0];
  EXPECT_EQ(c.name, "CameraNode");  // the camera itself has no name
  EXPECT_EQ(c.type, clpt::Camera::Type::Perspective);
  EXPECT_NEAR(c.yfov, 0.6f, 1e-6f);
  EXPECT_NEAR(c.aspect, 1.5f, 1e-6f);
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(c.camera_to_world[col][row], col == row ? 1.0f : 0.0f, 1e-6f);
  expect_near(glm::vec3(c.camera_to_world[3]), {10, 0, 10});
}

TEST(GltfLoader, StripFanMatrixAndMirror) {
  clpt::Scene s = load_ok(kValid / "strip_fan.gltf");
  expect_consistent(s, "strip_fan");
  // Node 0: strip (5 vertices, no indices) moved by a matrix to z = 5. Node 1: fan at x = 10.
  // Node 2: the strip mirrored by scale (-1,1,1) at x = 20. Node 3: LINES, skipped.
  ASSERT_EQ(s.positions.size(), 15u);
  ASSERT_EQ(s.triangles.size(), 9u);
  expect_near(s.positions[0], {0, 0, 5});
  expect_near(s.positions[4], {0, 2, 5});
  expect_near(s.positions[5], {10, 0, 0});
  expect_near(s.positions[9], {9, 1, 0});
  expect_near(s.positions[11], {19, 0, 0});
  // Strip: (v0 v1 v2) (v1 v3 v2) (v2 v3 v4), the odd one reordered to keep the winding.
  EXPECT_EQ(s.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(s.triangles[1], glm::uvec3(1, 3, 2));
  EXPECT_EQ(s.triangles[2], glm::uvec3(2, 3, 4));
  // Fan: (v1 v2 v0) (v2 v3 v0) (v3 v4 v0).
  EXPECT_EQ(s.triangles[3], glm::uvec3(6, 7, 5));
  EXPECT_EQ(s.triangles[4], glm::uvec3(7, 8, 5));
  EXPECT_EQ(s.triangles[5], glm::uvec3(8, 9, 5));
  // Mirror: negative determinant, so two indices of every triangle are swapped.
  EXPECT_EQ(s.triangles[6], glm::uvec3(10, 12, 11));
  EXPECT_EQ(s.triangles[7], glm::uvec3(11, 12, 13));
  EXPECT_EQ(s.triangles[8], glm::uvec3(12, 14, 13));
  // Every triangle, mirrored or not, faces +Z, and so do the (inverse-transpose) normals.
  for (size_t t = 0; t < s.triangles.size(); ++t) EXPECT_GT(geometric_normal(s, t).z, 0.0f) << "triangle " << t;
  for (size_t v = 0; v < 5; ++v) expect_near(s.normals[v], {0, 0, 1});
  for (size_t v = 5; v < 10; ++v) EXPECT_EQ(s.normals[v], glm::vec3(0.0f)) << "fan has no normals";
  for (size_t v = 10; v < 15; ++v) expect_near(s.normals[v], {0, 0, 1});
  ASSERT_EQ(s.materials.size(), 1u);  // one default material, shared
  for (uint32_t m : s.triangle_materials) EXPECT_EQ(m, 0u);
}

TEST(GltfLoader, FormatIsDetectedByMagicNotExtension) {
  clpt::Scene a = load_ok(kValid / "glb_content.gltf");
  clpt::Scene b = load_ok(kValid / "json_content.glb");
  EXPECT_EQ(a.triangles.size(), 1u);
  EXPECT_EQ(b.triangles.size(), 1u);
  EXPECT_EQ(a.positions, b.positions);
}

TEST(GltfLoader, UriDecodingAndBrokenImages) {
  // '+' in a file name (tinygltf 2.7 alone would look for "plus sign.bin").
  EXPECT_EQ(load_ok(kValid / "plus_uri.gltf").triangles.size(), 1u);
  // Percent-encoded buffer URI; the material's base colour image is not a PNG, its normal map
  // image is missing, its emissive image a data: URI of garbage (a fourth, unused, is WebP).
  // Each is an error naming the image; with --lenient a warning and a magenta texture.
  clpt::log::set_level(clpt::log::Level::Quiet);
  const std::string msg = load_error(kValid / "percent_uri_broken_images.gltf");
  EXPECT_NE(msg.find("image 0 'not_a_png.png' (used by material 0 baseColorTexture): not a PNG, JPEG or WebP image"),
            std::string::npos) << msg;
  EXPECT_NE(msg.find("--lenient"), std::string::npos) << msg;
  clpt::Scene s = clpt::load_gltf(kValid / "percent_uri_broken_images.gltf", clpt::LoadOptions{true, {}});
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.textures.size(), 3u);  // base colour, normal, emissive; the WebP one is unused
  for (const clpt::Texture& t : s.textures) {
    EXPECT_EQ(t.width, 1u);
    EXPECT_EQ(t.height, 1u);
    EXPECT_EQ(t.texels, std::vector<uint32_t>{0xFFFF00FFu}) << t.name;
  }
  EXPECT_TRUE(s.materials[0].base_color_texture.used());
  EXPECT_TRUE(s.materials[0].normal_texture.used());
  EXPECT_TRUE(s.materials[0].emissive_texture.used());
}

// ------------------------------------------------------------------------------------------
// Textures, material extensions and vertex attributes, from a quad written by the test.

// A folder under /tmp with `quad.gltf` (one quad, the given material and attributes) and two
// PNGs: `a.png` 2x1 RGBA (texels (255,0,0,255), (0,0,255,128)) and `b.png` 1x1 grey.
struct QuadFile {
  fs::path dir, file;
  QuadFile(const nlohmann::json& material, const nlohmann::json& node_extra, bool attributes) {
    char tmpl[] = "/tmp/tex-gltf-XXXXXX";
    dir = ::mkdtemp(tmpl);
    file = dir / "quad.gltf";
    auto png = [&](const char* name, int w, int nc, std::vector<unsigned char> px) {
      std::string why;
      ASSERT_TRUE(clpt::write_png(dir / name, uint32_t(w), 1, uint32_t(nc), 8, px.data(), {}, &why)) << name << ": " << why;
    };
    png("a.png", 2, 4, {255, 0, 0, 255, 0, 0, 255, 128});
    png("b.png", 1, 1, {100});
    // Positions, TEXCOORD_0, TEXCOORD_1, COLOR_0 (unorm8 VEC4), TANGENT, indices.
    std::vector<unsigned char> bin;
    auto put = [&](const void* p, size_t n) {
      const auto* b = static_cast<const unsigned char*>(p);
      bin.insert(bin.end(), b, b + n);
    };
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float uv1[8] = {0.5f, 0.25f, 0.75f, 0.25f, 0.75f, 0.5f, 0.5f, 0.5f};
    const unsigned char col[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 51, 255, 255, 255, 255};
    const float tan[16] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    put(pos, 48); put(uv0, 32); put(uv1, 32); put(col, 16); put(tan, 64); put(idx, 12);
    nlohmann::json doc = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {node_extra.is_null() ? nlohmann::json{{"mesh", 0}} : node_extra}},
        {"buffers", {{{"uri", "quad.bin"}, {"byteLength", bin.size()}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                         {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                         {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 32}},
                         {{"buffer", 0}, {"byteOffset", 112}, {"byteLength", 16}},
                         {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 64}},
                         {{"buffer", 0}, {"byteOffset", 192}, {"byteLength", 12}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                       {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                       {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                       {{"bufferView", 3}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC4"}},
                       {{"bufferView", 4}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}},
                       {{"bufferView", 5}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
        {"images", {{{"uri", "a.png"}}, {{"uri", "b.png"}}}},
        {"samplers", {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}, nlohmann::json::object()}},
        {"textures", {{{"source", 0}, {"sampler", 0}}, {{"source", 0}, {"sampler", 1}}, {{"source", 1}},
                      {{"source", 0}, {"sampler", 0}}}},
        {"materials", {material}},
    };
    nlohmann::json attrs = {{"POSITION", 0}, {"TEXCOORD_0", 1}};
    if (attributes) {
      attrs["TEXCOORD_1"] = 2;
      attrs["COLOR_0"] = 3;
      attrs["TANGENT"] = 4;
    }
    doc["meshes"] = {{{"primitives", {{{"attributes", attrs}, {"indices", 5}, {"material", 0}}}}}};
    std::ofstream(dir / "quad.bin", std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    std::ofstream(file) << doc.dump(1);
  }
  ~QuadFile() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// Every material field and extension is read; textures sharing an image and sampler share
// one decoded texture; samplers, sRGB-free 8-bit texels; KHR_texture_transform is folded into
// the hand-computed matrix T(offset) R(rotation) S(scale) and overrides texCoord.
TEST(GltfLoader, MaterialTexturesAndExtensions) {
  const nlohmann::json transform = {{"offset", {0.25, -0.5}}, {"rotation", 0.3}, {"scale", {2.0, 3.0}}, {"texCoord", 1}};
  const nlohmann::json material = {
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
        {"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}},
        {"metallicFactor", 0.3}, {"roughnessFactor", 0.6},
        {"metallicRoughnessTexture", {{"index", 3}, {"texCoord", 1}}}}},
      {"normalTexture", {{"index", 1}, {"scale", 0.5}}},
      {"occlusionTexture", {{"index", 2}}},
      {"emissiveTexture", {{"index", 2}}},
      {"emissiveFactor", {1.0, 0.5, 0.25}},
      {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true},
      {"extensions",
       {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
        {"KHR_materials_transmission", {{"transmissionFactor", 0.7}, {"transmissionTexture", {{"index", 2}}}}},
        {"KHR_materials_ior", {{"ior", 1.33}}},
        {"KHR_materials_specular", {{"specularFactor", 0.4}, {"specularColorFactor", {0.9, 0.8, 0.7}},
                                    {"specularTexture", {{"index", 2}}}, {"specularColorTexture", {{"index", 1}, {"texCoord", 1}}}}},
        {"KHR_materials_volume", {{"thicknessFactor", 1.0}, {"attenuationDistance", 2.5}, {"attenuationColor", {0.2, 0.4, 0.6}}}}}}};
  QuadFile q(material, nullptr, true);
  clpt::Scene s = load_ok(q.file);
  ASSERT_EQ(s.materials.size(), 1u);
  const clpt::Material& m = s.materials[0];
  EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  EXPECT_FLOAT_EQ(m.metallic, 0.3f);
  EXPECT_FLOAT_EQ(m.roughness, 0.6f);
  EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
  expect_near(m.emission, glm::vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(m.alpha_mode, clpt::Material::AlphaMode::Mask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_FLOAT_EQ(m.transmission, 0.7f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.specular, 0.4f);
  expect_near(m.specular_color, glm::vec3(0.9f, 0.8f, 0.7f));
  EXPECT_FLOAT_EQ(m.attenuation_distance, 2.5f);
  expect_near(m.attenuation_color, glm::vec3(0.2f, 0.4f, 0.6f));
  EXPECT_TRUE(m.volume);

  // Textures: glTF textures 0 and 3 (image a, clamp/mirror/nearest) share; 1 is image a with
  // the default sampler; 2 is image b. Occlusion is ignored (no texture of its own).
  ASSERT_EQ(s.textures.size(), 3u);
  EXPECT_EQ(m.base_color_texture.texture, m.metallic_roughness_texture.texture);
  EXPECT_NE(m.base_color_texture.texture, m.normal_texture.texture);
  EXPECT_EQ(m.emissive_texture.texture, m.transmission_texture.texture);
  EXPECT_EQ(m.specular_texture.texture, m.emissive_texture.texture);
  EXPECT_EQ(m.specular_color_texture.texture, m.normal_texture.texture);
  const clpt::Texture& a = s.textures[size_t(m.base_color_texture.texture)];
  EXPECT_EQ(a.width, 2u);
  EXPECT_EQ(a.height, 1u);
  EXPECT_EQ(a.texels, (std::vector<uint32_t>{0xFF0000FFu, 0x80FF0000u}));  // straight alpha
  EXPECT_EQ(a.wrap_s, clpt::Texture::Wrap::Clamp);
  EXPECT_EQ(a.wrap_t, clpt::Texture::Wrap::Mirror);
  EXPECT_TRUE(a.nearest);
  const clpt::Texture& a2 = s.textures[size_t(m.normal_texture.texture)];
  EXPECT_EQ(a2.texels, a.texels);
  EXPECT_EQ(a2.wrap_s, clpt::Texture::Wrap::Repeat);
  EXPECT_FALSE(a2.nearest);
  EXPECT_EQ(s.textures[size_t(m.emissive_texture.texture)].texels, std::vector<uint32_t>{0xFF646464u});  // grey -> RGB, A 255

  // texCoord: the transform's override (1), the textureInfo's (1), the default (0).
  EXPECT_EQ(m.base_color_texture.texcoord, 1u);
  EXPECT_EQ(m.metallic_roughness_texture.texcoord, 1u);
  EXPECT_EQ(m.normal_texture.texcoord, 0u);
  EXPECT_EQ(m.specular_color_texture.texcoord, 1u);
  const double c = std::cos(0.3), sn = std::sin(0.3);
  // T R S = [[sx c, sy s, ox], [-sx s, sy c, oy]] (KHR_texture_transform README's matrices).
  const glm::mat3x2& t = m.base_color_texture.transform;
  EXPECT_NEAR(t[0][0], 2.0 * c, 1e-6);
  EXPECT_NEAR(t[1][0], 3.0 * sn, 1e-6);
  EXPECT_NEAR(t[2][0], 0.25, 1e-6);
  EXPECT_NEAR(t[0][1], -2.0 * sn, 1e-6);
  EXPECT_NEAR(t[1][1], 3.0 * c, 1e-6);
  EXPECT_NEAR(t[2][1], -0.5, 1e-6);
  EXPECT_EQ(m.normal_texture.transform, glm::mat3x2(1.0f));
}

// TEXCOORD_1, COLOR_0 (normalized UNSIGNED_BYTE) and TANGENT under a mirroring node: the
// tangent follows the node's linear part and its w flips; positions and winding as before.
TEST(GltfLoader, VertexAttributesUnderMirror) {
  const nlohmann::json node = {{"mesh", 0}, {"scale", {-2.0, 1.0, 1.0}}};
  QuadFile q({{"name", "plain"}}, node, true);
  clpt::Scene s = load_ok(q.file);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.uvs1.size(), 4u);
  ASSERT_EQ(s.colors.size(), 4u);
  ASSERT_EQ(s.tangents.size(), 4u);
  EXPECT_EQ(s.uvs1[1], glm::vec2(0.75f, 0.25f));
  EXPECT_EQ(s.colors[0], glm::vec4(1, 0, 0, 1));
  EXPECT_NEAR(s.colors[2].w, 0.2f, 1e-6f);  // 51 / 255
  for (const glm::vec4& t : s.tangents) EXPECT_EQ(t, glm::vec4(-1, 0, 0, -1));
  // Without the attributes nothing is allocated.
  QuadFile plain({{"name", "plain"}}, nullptr, false);
  clpt::Scene p = load_ok(plain.file);
  EXPECT_TRUE(p.uvs1.empty());
  EXPECT_TRUE(p.colors.empty());
  EXPECT_TRUE(p.tangents.empty());
}

// A normal map without TANGENT: tangents are generated (+x along u, w = +1 with glTF UVs).
TEST(GltfLoader, TangentsGeneratedForNormalMaps) {
  QuadFile q({{"normalTexture", {{"index", 2}}}}, nullptr, false);
  clpt::Scene s = load_ok(q.file);
  ASSERT_EQ(s.tangents.size(), 4u);
  for (const glm::vec4& t : s.tangents) {
    EXPECT_NEAR(t.x, 1.0f, 1e-6f);
    EXPECT_NEAR(t.y, 0.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
  }
  EXPECT_TRUE(s.uvs1.empty());
  EXPECT_TRUE(s.colors.empty());
}

// ------------------------------------------------------------------------------------------
// scene.cpp

TEST(GltfScene, BoundsAndEmissiveCount) {
  clpt::Scene s;
  EXPECT_TRUE(s.bounds().empty());
  s.positions = {{-1, 0, 2}, {3, 4, -5}, {0, 1, 0}};
  s.normals.assign(3, glm::vec3(0));
  s.uvs.assign(3, glm::vec2(0));
  s.triangles = {{0, 1, 2}, {2, 1, 0}, {0, 2, 1}};
  clpt::Material plain, lamp, dim;
  lamp.emission = {0, 0, 2};
  dim.emission = {0, 0, 0};
  s.materials = {plain, lamp, dim};
  s.triangle_materials = {0, 1, 2};
  const clpt::Bounds b = s.bounds();
  EXPECT_EQ(b.min, glm::vec3(-1, 0, -5));
  EXPECT_EQ(b.max, glm::vec3(3, 4, 2));
  EXPECT_EQ(s.emissive_triangle_count(), 1u);
}

TEST(GltfScene, DefaultCameraFramesBounds) {
  clpt::Bounds b;
  b.extend(glm::vec3(-1, -2, -3));
  b.extend(glm::vec3(3, 2, 1));
  const clpt::Camera c = clpt::default_camera(b);
  EXPECT_EQ(c.type, clpt::Camera::Type::Perspective);
  EXPECT_NEAR(c.yfov, glm::radians(45.0f), 1e-6f);
  EXPECT_EQ(c.aspect, 0.0f);
  const glm::vec3 pos(c.camera_to_world[3]);
  const glm::vec3 center = b.center();
  EXPECT_NEAR(pos.x, center.x, 1e-5f);
  EXPECT_NEAR(pos.y, center.y, 1e-5f);
  EXPECT_GT(pos.z, center.z);
  expect_near(glm::vec3(c.camera_to_world[2]), {0, 0, 1});  // looks down -Z
  expect_near(glm::vec3(c.camera_to_world[1]), {0, 1, 0});
  // The bounding sphere fits in the vertical field of view, with a margin but not a huge one.
  const float radius = 0.5f * glm::length(b.extent());
  const float half_angle = std::asin(radius / (pos.z - center.z));
  EXPECT_LT(half_angle, 0.5f * c.yfov);
  EXPECT_GT(half_angle, 0.35f * c.yfov);
}

TEST(GltfScene, DefaultCameraForEmptyBounds) {
  const clpt::Camera c = clpt::default_camera(clpt::Bounds{});
  expect_near(glm::vec3(c.camera_to_world[3]), {0, 0, 1});
  expect_near(glm::vec3(c.camera_to_world[2]), {0, 0, 1});  // looks at the origin down -Z
}

// ------------------------------------------------------------------------------------------
// Fuzz: no input may crash or throw anything but clpt::Error(BadInput)

// Loads `iterations` random mutations and every truncation of `source`, written as fuzz<ext>
// in a private temporary folder next to copies of `support` files (e.g. its .bin).
void fuzz_file(const fs::path& source, const std::string& ext, int iterations, uint32_t seed,
               const std::vector<fs::path>& support = {}) {
  clpt::log::set_level(clpt::log::Level::Quiet);
  const std::vector<unsigned char> original = read_bytes(source);
  ASSERT_FALSE(original.empty()) << source;
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("clpt_gltf_fuzz_" + std::to_string(::getpid()) + "_" + std::to_string(seed));
  fs::create_directories(dir);
  for (const fs::path& f : support) fs::copy_file(f, dir / f.filename(), fs::copy_options::overwrite_existing);
  const fs::path path = dir / ("fuzz" + ext);
  std::mt19937 rng(seed);
  auto check = [&](const std::vector<unsigned char>& bytes, const std::string& what) {
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    LoadResult r = try_load(path);
    ASSERT_FALSE(r.other_exception) << what << ": " << r.message;
    if (!r.ok) ASSERT_EQ(r.code, clpt::ExitCode::BadInput) << what << ": " << r.message;
    else expect_consistent(r.scene, what);
  };
  // Every truncation.
  for (size_t n = 0; n < original.size(); n += std::max<size_t>(1, original.size() / 300))
    check(std::vector<unsigned char>(original.begin(), original.begin() + std::ptrdiff_t(n)),
          "truncated to " + std::to_string(n));
  // Random byte changes (digits are favoured so that JSON numbers change but stay JSON).
  for (int it = 0; it < iterations; ++it) {
    std::vector<unsigned char> bytes = original;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      size_t at = rng() % bytes.size();
      switch (rng() % 4) {
        case 0: bytes[at] = static_cast<unsigned char>(rng()); break;
        case 1: bytes[at] = static_cast<unsigned char>('0' + rng() % 10); break;
        case 2: bytes[at] ^= static_cast<unsigned char>(1u << (rng() % 8)); break;
        default: bytes[at] = 0xFF; break;
      }
    }
    check(bytes, "mutation " + std::to_string(it));
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST(GltfFuzz, MutatedGlb) { fuzz_file(kValid / "glb_content.gltf", ".glb", 1500, 1); }
TEST(GltfFuzz, MutatedJson) { fuzz_file(kValid / "strip_fan.gltf", ".gltf", 1500, 2); }
TEST(GltfFuzz, MutatedQuad) {
  fuzz_file(kValid / "quad_trs_u8.gltf", ".gltf", 1500, 3, {kValid / "quad_trs_u8.bin"});
}
TEST(GltfFuzz, MutatedSparse) {
  const fs::path dir = kShared / "SimpleSparseAccessor/glTF";
  REQUIRE_SHARED("SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf");
  fuzz_file(dir / "SimpleSparseAccessor.gltf", ".gltf", 1500, 4, {dir / "SimpleSparseAccessor.bin"});
}

}  // namespace

// WaterBottle: four 2048x2048 textures (base colour, metallic-roughness with occlusion
// packed in, normal, emissive), TANGENT from the file; the emissive texture makes it an
// emitter (emissiveFactor 1 x texture).
TEST(GltfConformance, WaterBottleTextures) {
  REQUIRE_SHARED("WaterBottle/glTF/WaterBottle.gltf");
  clpt::Scene s = load_ok(kShared / "WaterBottle/glTF/WaterBottle.gltf");
  EXPECT_GT(s.triangles.size(), 4000u);
  EXPECT_GT(s.emissive_triangle_count(), 0u);
  ASSERT_EQ(s.materials.size(), 1u);
  const clpt::Material& m = s.materials[0];
  EXPECT_TRUE(m.base_color_texture.used());
  EXPECT_TRUE(m.metallic_roughness_texture.used());
  EXPECT_TRUE(m.normal_texture.used());
  EXPECT_TRUE(m.emissive_texture.used());
  EXPECT_EQ(s.textures.size(), 4u);
  for (const clpt::Texture& t : s.textures) {
    EXPECT_EQ(t.width, 2048u) << t.name;
    EXPECT_EQ(t.texels.size(), size_t(t.width) * t.height) << t.name;
  }
  EXPECT_EQ(s.tangents.size(), s.positions.size());
}

}  // namespace gltf_loader_test
