#include "support/gltf_plane.h"

#include "scene/gltf_loader.h"
#include "support/device.h"
#include "support/scenes.h"

#include <cmath>
#include <cstdint>
#include <fstream>

#include <unistd.h>

namespace clpt::test {

namespace fs = std::filesystem;

namespace {
constexpr double kTilt = 55.0 * M_PI / 180.0, kHalf = 3.0;
}

glm::dvec3 tilted_plane_normal() { return {0.0, std::sin(kTilt), std::cos(kTilt)}; }

Scene load_tilted_plane(const fs::path& file) {
  Scene s = load_gltf(file);
  fs::remove_all(file.parent_path());
  return s;
}

FilmResult render_plane_under_sky(Scene scene, float yfov, uint32_t size, uint32_t spp, uint32_t seed) {
  add_camera_on_z(scene, 2.0f, yfov);
  RenderSettings rs;
  rs.width = rs.height = size;
  rs.spp = spp;
  rs.seed = seed;
  rs.background = glm::vec3(1.0f);
  Renderer r(device_context(), scene, rs);
  return r.render().film;
}

fs::path write_tilted_plane(const std::string& tag, const nlohmann::json& material,
                            const std::vector<std::string>& extensions) {
  const double t = kTilt, h = kHalf;
  // Corners of the square in its own (u, v) frame, rotated: v runs along (0, cos t, -sin t).
  auto corner = [&](double u, double v) {
    return std::vector<double>{u, v * std::cos(t), -v * std::sin(t)};
  };
  std::vector<float> pos;
  for (auto c : {corner(-h, -h), corner(h, -h), corner(h, h), corner(-h, h)})
    for (double x : c) pos.push_back(float(x));
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(pos.data()), pos.size() * 4);
  bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
  bin.append(2, '\0');
  const fs::path dir = fs::temp_directory_path() / ("clpt-" + tag + "-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "plane.bin", std::ios::binary) << bin;
  nlohmann::json mat = material;
  mat["doubleSided"] = true;
  nlohmann::json d = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}}}},
      {"materials", {mat}},
      {"buffers", {{{"uri", "plane.bin"}, {"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {-h, -h * std::cos(t), -h * std::sin(t)}},
                      {"max", {h, h * std::cos(t), h * std::sin(t)}}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
  };
  if (!extensions.empty()) d["extensionsUsed"] = extensions;
  std::ofstream(dir / "plane.gltf") << d.dump(1);
  return dir / "plane.gltf";
}

}  // namespace clpt::test
