#include "support/gltf_square.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>

#include <unistd.h>

#include "io/png_codec.h"

namespace clpt::test {

namespace fs = std::filesystem;

fs::path write_square(const std::string& tag, const nlohmann::json& material,
                      const std::vector<std::string>& extensions, const SquareImages& images) {
  const fs::path dir = fs::temp_directory_path() / ("clpt-" + tag + "-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const float h = float(kSquareHalf);
  const float pos[12] = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
  const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string bin;
  bin.append(reinterpret_cast<const char*>(pos), sizeof pos);
  bin.append(reinterpret_cast<const char*>(nrm), sizeof nrm);
  bin.append(reinterpret_cast<const char*>(uv), sizeof uv);
  bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
  bin.append(2, '\0');
  std::ofstream(dir / "square.bin", std::ios::binary) << bin;
  nlohmann::json used = extensions;
  used.push_back("KHR_lights_punctual");
  nlohmann::json d = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", used},
      {"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 4.0}}}}}}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 1}}}}},
      {"nodes", {{{"mesh", 0}},
                 {{"translation", {0.0, 0.0, 1.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                                    {"indices", 3}, {"material", 0}}}}}}},
      {"materials", {material}},
      {"buffers", {{{"uri", "square.bin"}, {"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
                       {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {-kSquareHalf, -kSquareHalf, 0.0}}, {"max", {kSquareHalf, kSquareHalf, 0.0}}},
                     {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                     {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                     {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
  };
  if (!images.empty()) {
    d["images"] = nlohmann::json::array();
    d["textures"] = nlohmann::json::array();
    for (const auto& [name, rgb] : images) {
      // clpt's own PNG writer: a fixture (tests/image_codecs_test.cpp checks the codec
      // against OpenImageIO), and this helper serves tests of both binaries.
      std::string why;
      EXPECT_TRUE(write_png(dir / name, 1, 1, 3, 8, rgb.data(), {}, &why)) << name << ": " << why;
      d["textures"].push_back({{"source", d["images"].size()}});
      d["images"].push_back({{"uri", name}});
    }
  }
  std::ofstream(dir / "square.gltf") << d.dump(1);
  return dir / "square.gltf";
}

}  // namespace clpt::test
