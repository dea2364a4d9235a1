// Compressed and quantized glTF geometry (host/scene/gltf/compression.cpp, accessors.cpp):
// KHR_draco_mesh_compression, EXT_meshopt_compression and KHR_mesh_quantization decode to the
// same world-space triangles and attributes as uncompressed data, and damaged or lying
// compressed data is bad input naming the file and the primitive.
//
//  CompressedGeometry: a mesh built here is written plain, Draco-coded (draco::Encoder) and
//                      meshopt-coded (meshoptimizer's encoders, with the octahedral filter),
//                      then damaged byte by byte and field by field.
//  GltfConformance:    the shared assets against their twins (Box, BoxMeshopt, Avocado), and
//                      every file of ../shared/scenes-extensions loads or is refused clearly.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <dlfcn.h>
#include <unistd.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_loader.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/log.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace compressed_geometry_test {
namespace {

const fs::path kShared = CLPT_SHARED_SCENES_DIR;
const fs::path kExtensions = CLPT_SHARED_EXTENSIONS_DIR;

constexpr int kFloat = 5126, kByte = 5120, kU16 = 5123, kU32 = 5125;

// ------------------------------------------------------------------------------------------
// Comparing scenes: every triangle of one matched to a distinct triangle of the other with the
// same corners (same winding, any rotation of the corners), within a tolerance per attribute.

struct Tolerance {
  float position, normal, uv;
};

struct Corner {
  glm::vec3 p, n;
  glm::vec2 uv;
};

// The UVs as the base colour texture reads them (through its KHR_texture_transform, which
// maps quantized UVs back to 0..1), or as stored when the material has no such texture.
std::vector<std::array<Corner, 3>> triangles_of(const clpt::Scene& s) {
  std::vector<std::array<Corner, 3>> out;
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const glm::uvec3& t = s.triangles[i];
    const clpt::TextureRef& tex = s.materials[s.triangle_materials[i]].base_color_texture;
    std::array<Corner, 3> c;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 uv = tex.used() ? tex.transform * glm::vec3(s.uvs[t[k]], 1.0f) : s.uvs[t[k]];
      c[size_t(k)] = {s.positions[t[k]], s.normals[t[k]], uv};
    }
    out.push_back(c);
  }
  return out;
}

bool corners_match(const std::array<Corner, 3>& a, const std::array<Corner, 3>& b, int rot, const Tolerance& tol,
                   float* worst) {
  for (int k = 0; k < 3; ++k) {
    const Corner& x = a[size_t(k)];
    const Corner& y = b[size_t((k + rot) % 3)];
    const float dp = glm::length(x.p - y.p), dn = glm::length(x.n - y.n), du = glm::length(x.uv - y.uv);
    if (dp > tol.position || dn > tol.normal || du > tol.uv) return false;
    worst[0] = std::max(worst[0], dp), worst[1] = std::max(worst[1], dn), worst[2] = std::max(worst[2], du);
  }
  return true;
}

// Fails the test (naming the first unmatched triangle) unless a and b hold the same triangles.
void expect_same_triangles(const clpt::Scene& a, const clpt::Scene& b, const Tolerance& tol) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  const auto ta = triangles_of(a), tb = triangles_of(b);
  std::vector<char> used(tb.size(), 0);
  float worst[3] = {0, 0, 0};
  for (size_t i = 0; i < ta.size(); ++i) {
    bool found = false;
    for (size_t j = 0; j < tb.size() && !found; ++j) {
      if (used[j]) continue;
      for (int rot = 0; rot < 3 && !found; ++rot)
        if (corners_match(ta[i], tb[j], rot, tol, worst)) {
          used[j] = 1;
          found = true;
        }
    }
    if (!found) {
      // The nearest candidate by corner positions, to say how far off the match is.
      float best = 1e30f, dn = 0, du = 0;
      for (size_t j = 0; j < tb.size(); ++j)
        for (int rot = 0; rot < 3; ++rot) {
          float dp = 0, n = 0, u = 0;
          for (int k = 0; k < 3; ++k) {
            const Corner &x = ta[i][size_t(k)], &y = tb[j][size_t((k + rot) % 3)];
            dp = std::max(dp, glm::length(x.p - y.p));
            n = std::max(n, glm::length(x.n - y.n));
            u = std::max(u, glm::length(x.uv - y.uv));
          }
          if (dp < best) best = dp, dn = n, du = u;
        }
      FAIL() << "triangle " << i << " has no twin within the tolerance; the nearest differs by position "
             << best << ", normal " << dn << ", uv " << du;
    }
  }
  std::cout << "largest differences: position " << worst[0] << ", normal " << worst[1] << ", uv " << worst[2]
            << "\n";
}

float diagonal(const clpt::Scene& s) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : s.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

// ------------------------------------------------------------------------------------------
// A mesh built here: a bumpy sphere (UV grid) with normals and UVs, 2 nu nv triangles.

struct Mesh {
  std::vector<float> positions, normals, uvs;  // 3, 3 and 2 floats per vertex
  std::vector<uint32_t> indices;
  size_t vertices() const { return positions.size() / 3; }
};

Mesh bumpy_sphere(int nu = 12, int nv = 8) {
  Mesh m;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const double u = double(i) / nu, v = double(j) / nv;
      const double phi = 2 * M_PI * u, theta = M_PI * (0.05 + 0.9 * v);
      const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      const double r = 1.0 + 0.1 * std::sin(5 * phi) * std::sin(3 * theta);
      for (int k = 0; k < 3; ++k) m.positions.push_back(float(r * d[k] + (k == 0 ? 2.0 : 0.0)));
      for (int k = 0; k < 3; ++k) m.normals.push_back(float(d[k]));
      m.uvs.push_back(float(u));
      m.uvs.push_back(float(v));
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1), d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  return m;
}

// A glTF document with one mesh node and the buffer `bin` (written next to it as scene.bin).
json document(const std::vector<std::string>& extensions) {
  json d = {{"asset", {{"version", "2.0"}, {"generator", "clpt tests/compressed_geometry_test.cpp"}}},
            {"scene", 0},
            {"scenes", json::array({{{"nodes", {0}}}})},
            {"nodes", json::array({{{"mesh", 0}, {"translation", {0.5, -1.0, 0.25}}}})},
            {"bufferViews", json::array()},
            {"accessors", json::array()}};
  if (!extensions.empty()) d["extensionsUsed"] = d["extensionsRequired"] = extensions;
  return d;
}

int add_view(json& d, std::vector<unsigned char>& bin, const void* data, size_t n, int stride = 0) {
  while (bin.size() % 4) bin.push_back(0);
  json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", n}};
  if (stride) v["byteStride"] = stride;
  const auto* p = static_cast<const unsigned char*>(data);
  bin.insert(bin.end(), p, p + n);
  d["bufferViews"].push_back(v);
  return int(d["bufferViews"].size()) - 1;
}

int add_accessor(json& d, int view, int component_type, size_t count, const char* type, bool normalized = false) {
  json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
  if (view >= 0) a["bufferView"] = view;
  if (normalized) a["normalized"] = true;
  d["accessors"].push_back(a);
  return int(d["accessors"].size()) - 1;
}

class CompressedGeometry : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/clpt-compressed-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    clpt::log::set_level(clpt::log::Level::Quiet);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // Writes `d` (its one buffer: `bin`, as an external file) and returns the .gltf's path.
  fs::path write(const std::string& name, json d, const std::vector<unsigned char>& bin) {
    d["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    std::ofstream(dir_ / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    const fs::path path = dir_ / (name + ".gltf");
    std::ofstream(path) << d.dump(1);
    return path;
  }

  fs::path write_plain(const Mesh& m) {
    json d = document({});
    std::vector<unsigned char> bin;
    const size_t n = m.vertices();
    const int pos = add_accessor(d, add_view(d, bin, m.positions.data(), m.positions.size() * 4), kFloat, n, "VEC3");
    const int nrm = add_accessor(d, add_view(d, bin, m.normals.data(), m.normals.size() * 4), kFloat, n, "VEC3");
    const int uv = add_accessor(d, add_view(d, bin, m.uvs.data(), m.uvs.size() * 4), kFloat, n, "VEC2");
    const int idx = add_accessor(d, add_view(d, bin, m.indices.data(), m.indices.size() * 4), kU32,
                                 m.indices.size(), "SCALAR");
    d["meshes"] = json::array(
        {{{"primitives", json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}},
                                       {"indices", idx}}})}}});
    return write("plain", d, bin);
  }

  // Draco-coded (edgebreaker, positions 14 bits, normals 10, UVs 12), with `edit` applied to
  // the document and `damage` to the Draco bytes before writing.
  fs::path write_draco(const Mesh& m, const std::string& name, const std::function<void(json&)>& edit = {},
                       const std::function<void(std::vector<unsigned char>&)>& damage = {}) {
    draco::Mesh dm;
    const size_t n = m.vertices();
    dm.set_num_points(uint32_t(n));
    auto add = [&](draco::GeometryAttribute::Type type, int ncomp, const std::vector<float>& values) {
      draco::GeometryAttribute ga;
      ga.Init(type, nullptr, int8_t(ncomp), draco::DT_FLOAT32, false, int64_t(sizeof(float)) * ncomp, 0);
      const int id = dm.AddAttribute(ga, true, uint32_t(n));
      for (size_t i = 0; i < n; ++i)
        dm.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &values[i * size_t(ncomp)]);
      return int(dm.attribute(id)->unique_id());
    };
    const int pos = add(draco::GeometryAttribute::POSITION, 3, m.positions);
    const int nrm = add(draco::GeometryAttribute::NORMAL, 3, m.normals);
    const int uv = add(draco::GeometryAttribute::TEX_COORD, 2, m.uvs);
    for (size_t t = 0; t < m.indices.size(); t += 3)
      dm.AddFace({draco::PointIndex(m.indices[t]), draco::PointIndex(m.indices[t + 1]),
                  draco::PointIndex(m.indices[t + 2])});
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
    draco::EncoderBuffer out;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(dm, &out).ok());
    std::vector<unsigned char> coded(out.data(), out.data() + out.size());
    if (damage) damage(coded);

    json d = document({"KHR_draco_mesh_compression"});
    std::vector<unsigned char> bin;
    const int view = add_view(d, bin, coded.data(), coded.size());
    // Edgebreaker keeps this manifold mesh's point count; accessors carry the counts.
    const int a_pos = add_accessor(d, -1, kFloat, n, "VEC3");
    const int a_nrm = add_accessor(d, -1, kFloat, n, "VEC3");
    const int a_uv = add_accessor(d, -1, kFloat, n, "VEC2");
    const int a_idx = add_accessor(d, -1, kU32, m.indices.size(), "SCALAR");
    d["meshes"] = json::array({{{"primitives",
                                 json::array({{{"attributes", {{"POSITION", a_pos}, {"NORMAL", a_nrm}, {"TEXCOORD_0", a_uv}}},
                                               {"indices", a_idx},
                                               {"extensions",
                                                {{"KHR_draco_mesh_compression",
                                                  {{"bufferView", view},
                                                   {"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}}}}}}}})}}});
    if (edit) edit(d);
    return write(name, d, bin);
  }

  // meshopt-coded: positions float (ATTRIBUTES), normals as 8-bit octahedral (filter
  // OCTAHEDRAL, BYTE normalized under KHR_mesh_quantization), UVs float, indices TRIANGLES;
  // the fallback buffer 1 has no data. `edit` and `damage` as for write_draco.
  fs::path write_meshopt(const Mesh& m, const std::string& name, const std::function<void(json&)>& edit = {},
                         const std::function<void(std::vector<unsigned char>&)>& damage = {}) {
    const size_t n = m.vertices();
    json d = document({"EXT_meshopt_compression", "KHR_mesh_quantization"});
    std::vector<unsigned char> bin;
    size_t fallback_size = 0;
    auto add = [&](const void* raw, size_t count, size_t stride, const char* mode, const char* filter) {
      std::vector<unsigned char> coded;
      if (std::string(mode) == "ATTRIBUTES") {
        coded.resize(meshopt_encodeVertexBufferBound(count, stride));
        coded.resize(meshopt_encodeVertexBuffer(coded.data(), coded.size(), raw, count, stride));
      } else {
        coded.resize(meshopt_encodeIndexBufferBound(count, n));
        coded.resize(meshopt_encodeIndexBuffer(coded.data(), coded.size(), static_cast<const unsigned int*>(raw), count));
      }
      if (damage) damage(coded);
      while (bin.size() % 4) bin.push_back(0);
      json ext = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", coded.size()},
                  {"byteStride", stride}, {"count", count}, {"mode", mode}};
      if (filter) ext["filter"] = filter;
      bin.insert(bin.end(), coded.begin(), coded.end());
      json v = {{"buffer", 1}, {"byteOffset", fallback_size}, {"byteLength", count * stride},
                {"extensions", {{"EXT_meshopt_compression", ext}}}};
      if (std::string(mode) == "ATTRIBUTES") v["byteStride"] = stride;
      fallback_size += (count * stride + 3) / 4 * 4;
      d["bufferViews"].push_back(v);
      return int(d["bufferViews"].size()) - 1;
    };
    std::vector<float> n4;
    for (size_t i = 0; i < n; ++i) n4.insert(n4.end(), {m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2], 0});
    std::vector<unsigned char> oct(n * 4);
    meshopt_encodeFilterOct(oct.data(), n, 4, 8, n4.data());
    const int pos = add_accessor(d, add(m.positions.data(), n, 12, "ATTRIBUTES", nullptr), kFloat, n, "VEC3");
    const int nrm = add_accessor(d, add(oct.data(), n, 4, "ATTRIBUTES", "OCTAHEDRAL"), kByte, n, "VEC3", true);
    const int uv = add_accessor(d, add(m.uvs.data(), n, 8, "ATTRIBUTES", nullptr), kFloat, n, "VEC2");
    const int idx = add_accessor(d, add(m.indices.data(), m.indices.size(), 4, "TRIANGLES", nullptr), kU32,
                                 m.indices.size(), "SCALAR");
    d["meshes"] = json::array(
        {{{"primitives", json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}},
                                       {"indices", idx}}})}}});
    if (edit) edit(d);
    const fs::path path = write(name, d, bin);
    // The fallback buffer: a byteLength and no data, as gltfpack writes it.
    json full = json::parse(std::ifstream(path));
    full["buffers"].push_back({{"byteLength", fallback_size}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    std::ofstream(path) << full.dump(1);
    return path;
  }

  // The one-line BadInput message of a file that must not load; it names the file.
  std::string error_of(const fs::path& path) {
    try {
      clpt::load_gltf(path);
    } catch (const clpt::Error& e) {
      EXPECT_EQ(e.code(), clpt::ExitCode::BadInput) << e.what();
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      return msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "non-clpt exception: " << e.what();
      return "";
    }
    ADD_FAILURE() << path << " loaded, but it should not";
    return "";
  }

  fs::path dir_;
};

// libdraco.a carries its own tinygltf; the link order in CMakeLists.txt keeps it out. Were
// it in, the loader would mix two tinygltf versions (every load crashed when it happened).
TEST(CompressedGeometryLink, TinygltfIsDebiansOwn) {
  Dl_info info{};
  auto load = &tinygltf::TinyGLTF::LoadASCIIFromString;
  void* address;
  std::memcpy(&address, &load, sizeof address);
  ASSERT_NE(::dladdr(address, &info), 0);
  ASSERT_NE(info.dli_fname, nullptr);
  EXPECT_NE(std::string(info.dli_fname).find("libtinygltf"), std::string::npos)
      << "tinygltf::TinyGLTF::LoadASCIIFromString is defined in " << info.dli_fname
      << ", not in Debian's libtinygltf (libdraco.a's copy was linked in)";
}

TEST_F(CompressedGeometry, DracoDecodesToThePlainTriangles) {
  const Mesh m = bumpy_sphere();
  const clpt::Scene plain = clpt::load_gltf(write_plain(m));
  const clpt::Scene draco = clpt::load_gltf(write_draco(m, "draco"));
  ASSERT_EQ(plain.triangles.size(), 2u * 12 * 8);
  // Quantisation steps: positions 14 bits over the 2.2-unit box (1.4e-4), normals 10 bits
  // (octahedral, about 3e-3), UVs 12 bits over 0..1 (2.4e-4); the bounds allow twice that.
  expect_same_triangles(plain, draco, {3e-4f, 6e-3f, 5e-4f});
}

TEST_F(CompressedGeometry, MeshoptDecodesToThePlainTriangles) {
  const Mesh m = bumpy_sphere();
  const clpt::Scene plain = clpt::load_gltf(write_plain(m));
  const clpt::Scene meshopt = clpt::load_gltf(write_meshopt(m, "meshopt"));
  // Positions and UVs are coded losslessly; normals through 8-bit octahedral (step 1/127).
  expect_same_triangles(plain, meshopt, {1e-6f, 2e-2f, 1e-7f});
}

// Each damaged or lying file, and the message it must give. The mutations prove the twin
// tests above read the compressed bytes: a decoder that ignored them could not fail here.
TEST_F(CompressedGeometry, DamagedDracoIsBadInput) {
  const Mesh m = bumpy_sphere();
  auto truncate = [](std::vector<unsigned char>& b) { b.resize(b.size() / 2); };
  EXPECT_NE(error_of(write_draco(m, "draco_truncated", {}, truncate)).find("Draco cannot decode bufferView 0"),
            std::string::npos);
  // Draco data has no checksum: a flipped byte may decode to other geometry. Each of these
  // either loads or is bad input naming the file; none crashes or throws anything else.
  size_t refused = 0;
  for (size_t at = 0; at < 64; ++at) {
    auto flip = [at](std::vector<unsigned char>& b) { b[at * b.size() / 64] ^= 0xA5; };
    const fs::path path = write_draco(m, "draco_flipped_" + std::to_string(at), {}, flip);
    try {
      clpt::load_gltf(path);
    } catch (const clpt::Error& e) {
      EXPECT_EQ(e.code(), clpt::ExitCode::BadInput) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(refused, 0u);  // the header bytes at least are checked
  auto more_points = [](json& d) { d["accessors"][0]["count"] = d["accessors"][0]["count"].get<int>() + 1; };
  EXPECT_NE(error_of(write_draco(m, "draco_count_lie", more_points)).find("but the Draco data has 117 points"),
            std::string::npos);
  auto fewer_indices = [](json& d) { d["accessors"][3]["count"] = 3; };
  EXPECT_NE(error_of(write_draco(m, "draco_index_lie", fewer_indices)).find("but the Draco data has 192 triangles"),
            std::string::npos);
  auto no_attribute = [](json& d) {
    d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 7;
  };
  EXPECT_NE(error_of(write_draco(m, "draco_no_attribute", no_attribute)).find("names Draco attribute 7, which the"),
            std::string::npos);
  // 325 points: the indices do not fit 8 bits.
  const Mesh big = bumpy_sphere(24, 12);
  auto u8_indices = [](json& d) { d["accessors"][3]["componentType"] = 5121; };
  EXPECT_NE(error_of(write_draco(big, "draco_u8_indices", u8_indices)).find("does not fit the indices accessor's 8-bit"),
            std::string::npos);
  auto huge = [](json& d) { d["accessors"][0]["count"] = 2000000000; };
  EXPECT_NE(error_of(write_draco(m, "draco_huge", huge)).find("more than the limit of 1073741824"),
            std::string::npos);
}

TEST_F(CompressedGeometry, DamagedMeshoptIsBadInput) {
  const Mesh m = bumpy_sphere();
  auto truncate = [](std::vector<unsigned char>& b) { b.resize(b.size() / 2); };
  EXPECT_NE(error_of(write_meshopt(m, "meshopt_truncated", {}, truncate)).find("meshoptimizer cannot decode"),
            std::string::npos);
  auto count_lie = [](json& d) {
    auto& ext = d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"];
    ext["count"] = ext["count"].get<int>() * 4;
  };
  EXPECT_NE(error_of(write_meshopt(m, "meshopt_count_lie", count_lie)).find("meshoptimizer cannot decode"),
            std::string::npos);
  auto filter_on_indices = [](json& d) { d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["filter"] = "OCTAHEDRAL"; };
  EXPECT_NE(error_of(write_meshopt(m, "meshopt_filter", filter_on_indices)).find("has filter 'OCTAHEDRAL' on TRIANGLES"),
            std::string::npos);
  auto quat_stride = [](json& d) { d["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["filter"] = "QUATERNION"; };
  EXPECT_NE(error_of(write_meshopt(m, "meshopt_quat", quat_stride)).find("QUATERNION' with byteStride 4"),
            std::string::npos);
  auto unquantized = [](json& d) {
    d["extensionsUsed"] = d["extensionsRequired"] = json::array({"EXT_meshopt_compression"});
  };
  EXPECT_NE(error_of(write_meshopt(m, "meshopt_unquantized", unquantized))
                .find("integer attributes need KHR_mesh_quantization"),
            std::string::npos);
}

// ------------------------------------------------------------------------------------------
// The shared assets

#define REQUIRE_FILE(path)                                                                    \
  do {                                                                                        \
    if (!fs::exists(path)) GTEST_SKIP() << (path) << " not found (../shared absent)";        \
  } while (0)

TEST(GltfConformance, DracoBoxMatchesItsUncompressedTwin) {
  REQUIRE_FILE(kShared / "Box/glTF-Draco/Box.gltf");
  const clpt::Scene plain = clpt::load_gltf(kShared / "Box/glTF/Box.gltf");
  const clpt::Scene draco = clpt::load_gltf(kShared / "Box/glTF-Draco/Box.gltf");
  // Box is 1 unit across; the Draco file's positions use 11 bits (step 4.9e-4).
  expect_same_triangles(plain, draco, {1e-3f, 1e-3f, 1.0f});
}

TEST(GltfConformance, MeshoptBoxMatchesItsUncompressedTwin) {
  REQUIRE_FILE(kExtensions / "BoxMeshopt/BoxMeshopt.glb");
  REQUIRE_FILE(kShared / "Box/glTF/Box.gltf");
  const clpt::Scene plain = clpt::load_gltf(kShared / "Box/glTF/Box.gltf");
  const clpt::Scene meshopt = clpt::load_gltf(kExtensions / "BoxMeshopt/BoxMeshopt.glb");
  // gltfpack: u16 positions with 14 bits over 1 unit (step 6.1e-5), normals as normalized i8.
  expect_same_triangles(plain, meshopt, {2e-4f, 1e-2f, 1.0f});
  // The .gltf variant (octahedral normals, an extra rotation node): same triangles up to that
  // rotation, so the same area and count.
  const clpt::Scene rotated = clpt::load_gltf(kExtensions / "BoxMeshopt/BoxMeshopt.gltf");
  ASSERT_EQ(rotated.triangles.size(), plain.triangles.size());
  EXPECT_NEAR(diagonal(rotated), diagonal(plain), 1e-3f);
}

TEST(GltfConformance, DracoAvocadoMatchesItsQuantizedTwin) {
  REQUIRE_FILE(kExtensions / "Avocado/glTF-Draco/Avocado.gltf");
  const clpt::Scene draco = clpt::load_gltf(kExtensions / "Avocado/glTF-Draco/Avocado.gltf");
  const clpt::Scene quantized = clpt::load_gltf(kExtensions / "Avocado/glTF-Quantized/Avocado.gltf");
  // Both lose precision differently (Draco's quantisation, gltfpack's u16 positions and i8
  // normals); the bounds are a few steps of the coarser: 0.5 % of the 6 cm avocado, 8-bit normals.
  const float d = diagonal(quantized);
  EXPECT_GT(d, 0.05f);
  expect_same_triangles(quantized, draco, {5e-3f * d, 4e-2f, 2e-3f});
}

// Every file in ../shared/scenes-extensions loads, except the ones that need what Debian
// cannot decode (KTX2 images), which are refused naming the file and the reason.
TEST(GltfConformance, EveryExtensionAssetLoadsOrIsRefusedClearly) {
  if (!fs::is_directory(kExtensions)) GTEST_SKIP() << kExtensions << " not found (../shared absent)";
  clpt::log::set_level(clpt::log::Level::Quiet);
  const std::map<std::string, std::string> refusals = {
      {"StainedGlassLamp/glTF-KTX-BasisU/StainedGlassLamp.gltf", "requires extension KHR_texture_basisu"},
      {"AnisotropyBarnLamp/glTF-KTX2-Basisu/AnisotropyBarnLamp.gltf", "a KTX2 (Basis Universal) image"},
  };
  size_t loaded = 0;
  std::set<std::string> refused;
  for (const auto& entry : fs::recursive_directory_iterator(kExtensions)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
    const std::string rel = entry.path().lexically_relative(kExtensions).generic_string();
    SCOPED_TRACE(rel);
    try {
      const clpt::Scene s = clpt::load_gltf(entry.path());
      EXPECT_FALSE(s.triangles.empty());
      EXPECT_EQ(refusals.count(rel), 0u) << "loaded, but clpt cannot decode all of it";
      ++loaded;
    } catch (const clpt::Error& e) {
      refused.insert(rel);
      auto it = refusals.find(rel);
      ASSERT_NE(it, refusals.end()) << "refused: " << e.what();
      EXPECT_EQ(e.code(), clpt::ExitCode::BadInput);
      EXPECT_NE(std::string(e.what()).find(entry.path().filename().string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(it->second), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(refused.size(), refusals.size());
  EXPECT_GE(loaded, 19u);
}

}  // namespace

}  // namespace compressed_geometry_test
