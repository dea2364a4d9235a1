// Texture footprints end to end (host/render/mipmaps.cpp, the ray cone of
// kernels/integrators/stages/walk.cl, kernels/geometry/surface.cl's level, the trilinear
// lookup of kernels/texture/texture.cl), on a written glTF file:
//   TextureLod   a square with a checker of 1-texel squares (black and white, sRGB), 256
//                texels across, facing a camera that sees 8 x 8 texels in each pixel, lit by
//                a constant white sky: each pixel shows the texture's mean over its
//                footprint, 0.5 in linear light (light found by BSDF sampling only: no
//                lighting noise). At full resolution (--texture-filter
//                bilinear) every sample sees about one texel: the pixels are right on average
//                and very noisy; with mip maps every sample reads level 3, already the mean.
//                The full-resolution image's mean is 0.5 (z-test), the filtered one's the
//                level's 8-bit value of it, 0.502886 (mip maps averaged in sRGB values would
//                give 0.216), and the texture's share of the sample variance (the variance
//                less that of the same scene with a uniform texture) falls by more than 50x.
//                A mirror in front of the camera shows the same checker through one
//                reflection: the cone goes on through it, so the same holds. On a ground
//                plane receding to the horizon, a 1-sample image with mip maps is close to
//                the 1 024-sample one where a full-resolution one is not (relMSE).
// The levels themselves and the kernel's lookup between them are in tests/texture_test.cpp
// (Mipmaps, TextureLod.TrilinearBetweenLevels).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/png_codec.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "util/log.h"

#include <unistd.h>

namespace clpt::texture_lod_test {
namespace {

namespace fs = std::filesystem;
constexpr int kTexels = 256;   // the checker's side, in texels (1-texel squares)
constexpr uint32_t kSize = 32;  // pixels: 8 texels per pixel where the square fills the image

// square.gltf: the checkered square [-1, 1]^2 at z = 0 facing +z, UVs across it (with `flat`,
// the checker's level-1 value everywhere, sRGB 188); with
// `mirror`, the square stands at x = -3 facing +x instead and a mirror (metal, roughness 0)
// at the origin, tilted 45 degrees about y, shows it to a camera on the z axis.
enum class Layout { Facing, Mirror, Receding };

fs::path write_scene(const std::string& tag, Layout layout, bool flat) {
  const bool mirror = layout == Layout::Mirror, receding = layout == Layout::Receding;
  // Receding: a 60 m square lying at y = 0 in front of the camera (z from 0 to -60), the
  // checker repeated 60 times across it (a texel is 3.9 mm).
  const float half = receding ? 30.0f : 1.0f, tiles = receding ? 60.0f : 1.0f;
  const fs::path dir = fs::temp_directory_path() / ("clpt-lod-" + tag + "-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<unsigned char> px(size_t(kTexels) * kTexels * 3);
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      for (int c = 0; c < 3; ++c) px[(size_t(y) * kTexels + x) * 3 + c] = flat ? 188 : (x + y) % 2 ? 255 : 0;
  std::string why;
  EXPECT_TRUE(write_png(dir / "checker.png", uint32_t(kTexels), uint32_t(kTexels), 3, 8, px.data(), {}, &why)) << why;
  // Two quads: the checker (mesh 0) and the mirror (mesh 1), 4 vertices each.
  const float square[12] = {-half, -half, 0, half, -half, 0, half, half, 0, -half, half, 0};
  const float h = 1.5f;  // the mirror's half size
  const float mirror_pos[12] = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
  const float normal[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const float uv[8] = {0, tiles, tiles, tiles, tiles, 0, 0, 0};
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string bin;
  for (const auto& part : {std::string(reinterpret_cast<const char*>(square), 48),
                           std::string(reinterpret_cast<const char*>(normal), 48),
                           std::string(reinterpret_cast<const char*>(uv), 32),
                           std::string(reinterpret_cast<const char*>(idx), 12) + std::string(4, '\0'),
                           std::string(reinterpret_cast<const char*>(mirror_pos), 48)})
    bin += part;
  std::ofstream(dir / "square.bin", std::ios::binary) << bin;
  using nlohmann::json;
  const double s = std::sqrt(0.5);
  json nodes = json::array();
  // The checker: at the origin, or turned to face +x at x = -3 (rotation +90 degrees about y).
  if (mirror)
    nodes.push_back({{"mesh", 0}, {"translation", {-3.0, 0.0, 0.0}}, {"rotation", {0.0, s, 0.0, s}}});
  else if (receding)  // turned -90 degrees about x: its normal +z becomes +y
    nodes.push_back({{"mesh", 0}, {"translation", {0.0, 0.0, -30.0}}, {"rotation", {-s, 0.0, 0.0, s}}});
  else
    nodes.push_back({{"mesh", 0}});
  auto mesh = [](int position, int material, bool uvs) {
    json attributes = {{"POSITION", position}, {"NORMAL", 1}};
    if (uvs) attributes["TEXCOORD_0"] = 2;
    json primitive = {{"attributes", attributes}, {"indices", 3}, {"material", material}};
    return json{{"primitives", json::array({primitive})}};
  };
  json meshes = json::array({mesh(0, 0, true)});
  json materials = json::array({json{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}},
                                     {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}}});
  if (mirror) {
    // Normal +z turned -45 degrees about y: (-0.71, 0, 0.71), halfway between +z (to the
    // camera) and -x (to the checker).
    const double a = std::sin(-M_PI / 8.0), b = std::cos(-M_PI / 8.0);
    nodes.push_back({{"mesh", 1}, {"rotation", {0.0, a, 0.0, b}}});
    meshes.push_back(mesh(4, 1, false));
    materials.push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 1.0},
                                                   {"roughnessFactor", 0.0}}}});
  }
  json nodes_index = json::array();
  for (size_t i = 0; i < nodes.size(); ++i) nodes_index.push_back(i);
  json d = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_materials_specular"}},
      {"scene", 0},
      {"scenes", {{{"nodes", nodes_index}}}},
      {"nodes", nodes},
      {"meshes", meshes},
      {"materials", materials},
      {"images", {{{"uri", "checker.png"}}}},
      {"samplers", {{{"minFilter", 9987}, {"magFilter", 9729}}}},
      {"textures", {{{"source", 0}, {"sampler", 0}}}},
      {"buffers", {{{"uri", "square.bin"}, {"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
                       {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}},
                       {{"buffer", 0}, {"byteOffset", 144}, {"byteLength", 48}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {-half, -half, 0.0}}, {"max", {half, half, 0.0}}},
                     {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                     {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                     {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
                     {{"bufferView", 4}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {-h, -h, 0.0}}, {"max", {h, h, 0.0}}}}},
  };
  std::ofstream(dir / "square.gltf") << d.dump(1);
  return dir / "square.gltf";
}

struct Shot {
  double mean = 0.0, sigma = 0.0;  // the image's mean (channel 0) and its standard error
  double sample_variance = 0.0;    // the pixels' mean sample variance
  std::vector<double> pixels;      // channel 0
};

// The checker seen by a camera at (0, 0, 2) whose view just spans it (tan(fov / 2) = 0.5: 8
// texels a pixel), or through the mirror (the path to the checker about 1 + 3 = 4 m long; the
// view's tangent 0.125 keeps it inside the checker's middle, 4 texels a pixel).
Shot render(bool mirror, bool mipmaps, uint32_t spp, uint32_t seed, bool flat = false,
            const std::string& integrator = "pt") {
  const fs::path file = write_scene(std::to_string(seed) + (mirror ? "m" : "p") + integrator,
                                    mirror ? Layout::Mirror : Layout::Facing, flat);
  log::set_level(log::Level::Quiet);
  Scene scene = load_gltf(file);
  fs::remove_all(file.parent_path());
  Camera cam;
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(0.0f, 0.0f, mirror ? 1.0f : 2.0f, 1.0f);
  cam.yfov = float(2.0 * std::atan(mirror ? 0.125 : 0.5));
  cam.aspect = 1.0f;
  scene.cameras.push_back(cam);
  RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.spp = spp;
  rs.seed = seed;
  rs.max_depth = 8;
  rs.background = glm::vec3(1.0f);
  rs.mipmaps = mipmaps;
  rs.integrator = integrator;
  // Light found by BSDF sampling alone: a Lambertian surface under a sky of radiance 1 (or a
  // white mirror showing it) then returns its albedo with no lighting noise, so what varies
  // between a pixel's samples is the texture alone.
  rs.direct = dev::DIRECT_BSDF;
  Renderer r(test::device_context(), scene, rs);
  const FilmResult f = r.render().film;
  EXPECT_EQ(f.dropped_samples, 0u);
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  Shot s;
  double var = 0.0;
  const size_t n = size_t(kSize) * kSize;
  for (size_t p = 0; p < n; ++p) {
    s.mean += f.mean.rgb[p * 3];
    var += v.rgb[p * 3];
    s.sample_variance += f.variance.rgb[p * 3];
    s.pixels.push_back(f.mean.rgb[p * 3]);
  }
  s.mean /= double(n);
  s.sigma = std::sqrt(var) / double(n);
  s.sample_variance /= double(n);
  return s;
}

void check_pair(bool mirror) {
  const Shot full = render(mirror, false, 64, 1), mip = render(mirror, true, 64, 2);
  // What the light alone adds to the variance (seen through the mirror: 0.0515, on the open
  // plane 0): the same scene with a uniform texture.
  const Shot flat = render(mirror, true, 64, 2, true);  // the same seed: the same light paths
  std::cout << "[ lod      ] " << (mirror ? "through a mirror" : "direct") << ": bilinear mean " << full.mean << " ("
            << full.sigma << "), sample variance " << full.sample_variance << "; trilinear mean " << mip.mean << " ("
            << mip.sigma << "), sample variance " << mip.sample_variance << "; uniform texture: sample variance "
            << flat.sample_variance << "\n";
  // Level 0's checker averages to linear 0.5; every level below it holds that mean as the
  // 8-bit sRGB value 188, which decodes to 0.502886 (the levels' rounding: 0.6 % here).
  // Mip levels averaged in sRGB values would hold 128: 0.216.
  const double z = 4.0;
  EXPECT_NEAR(full.mean, 0.5, z * full.sigma) << "full resolution: the texture's mean";
  EXPECT_NEAR(mip.mean, 0.502886, z * mip.sigma + 1e-4) << "mip levels: the level's value";
  EXPECT_LT((mip.sample_variance - flat.sample_variance) * 50.0, full.sample_variance - flat.sample_variance)
      << "the footprint's mean, not one texel";
}

// The picture: the checker on a ground plane receding to the horizon, seen from 1 m
// above by a 48 x 32 camera looking along it (fov 60 degrees: its lower half is the plane, a
// pixel there covers 16 texels or more). A 1-sample image with mip maps is close to the
// 1 024-sample one (the pixels' true means) in every row below the horizon, where a 1-sample
// full-resolution image is not: relMSE = mean (I - R)^2 / (R^2 + 1e-3).
TEST(TextureLod, RecedingCheckerAtOneSample) {
  const fs::path file = write_scene("recede", Layout::Receding, false);
  log::set_level(log::Level::Quiet);
  Scene scene = load_gltf(file);
  fs::remove_all(file.parent_path());
  Camera cam;
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(0.0f, 1.0f, 0.0f, 1.0f);
  cam.yfov = float(M_PI / 3.0);
  cam.aspect = 1.5f;
  scene.cameras.push_back(cam);
  constexpr uint32_t w = 48, h = 32;
  auto shoot = [&](bool mipmaps, uint64_t spp, uint32_t seed) {
    RenderSettings rs;
    rs.width = w;
    rs.height = h;
    rs.spp = spp;
    rs.seed = seed;
    rs.max_depth = 2;
    rs.background = glm::vec3(1.0f);
    rs.direct = dev::DIRECT_BSDF;  // as above: the texture is all that varies
    rs.mipmaps = mipmaps;
    Renderer r(test::device_context(), scene, rs);
    return r.render().film.mean;
  };
  const Image reference = shoot(false, 1024, 7), mip = shoot(true, 1, 8), full = shoot(false, 1, 9);
  // Rows 18 to 31: the plane alone (the horizon is row 16, the plane's far edge half a row
  // below it).
  auto rel_mse = [&](const Image& im) {
    double sum = 0.0;
    size_t n = 0;
    for (uint32_t y = 18; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x, ++n) {
        const size_t p = (size_t(y) * w + x) * 3;
        const double r = reference.rgb[p], d = im.rgb[p] - r;
        sum += d * d / (r * r + 1e-3);
      }
    return sum / double(n);
  };
  const double e_mip = rel_mse(mip), e_full = rel_mse(full);
  std::cout << "[ lod      ] receding checker, 1 spp against 1 024: relMSE mip maps " << e_mip
            << ", full resolution " << e_full << "\n";
  EXPECT_LT(e_mip, 0.01);
  EXPECT_GT(e_full, 10.0 * e_mip);
}

TEST(TextureLod, FootprintFiltersTheChecker) { check_pair(false); }

TEST(TextureLod, ConeGoesOnThroughAMirror) { check_pair(true); }

// The other integrators' camera paths: bdpt's and vcm's camera subpaths, pm's and sppm's
// visible points. Their films keep no per-pixel sample variance (splats, shared photon maps),
// so the test compares images instead: rendered with one seed, the checker at full
// resolution, with mip maps, and the uniform texture of the checker's level-1 value. Every
// level a pixel's footprint reads (3, or 2 through the mirror) holds that value, so where the
// camera side reads the footprint the mip-mapped image is the uniform one (the same paths and
// the same texel values) and the checker's noise is gone: the mean squared difference to the
// uniform image falls by more than 50x. What is left comes from reads at full resolution: the
// light side's (bdpt's and vcm's light subpaths connected to the camera, photons scattered
// by the checker). A camera side without cones leaves the full-resolution difference.
double mean_squared_difference(const Shot& a, const Shot& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += (a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
  return sum / double(a.pixels.size());
}

void check_camera_side(bool mirror, const std::string& integrator) {
  const Shot full = render(mirror, false, 64, 3, false, integrator);
  const Shot mip = render(mirror, true, 64, 3, false, integrator);
  const Shot flat = render(mirror, true, 64, 3, true, integrator);
  const double d_full = mean_squared_difference(full, flat), d_mip = mean_squared_difference(mip, flat);
  std::cout << "[ lod      ] " << integrator << ", " << (mirror ? "through a mirror" : "direct")
            << ": mean squared difference to the uniform texture's image, bilinear " << d_full << ", trilinear "
            << d_mip << "\n";
  EXPECT_GT(d_full, 0.0);
  EXPECT_LT(d_mip * 50.0, d_full) << "the camera side reads the footprint's mean";
}

TEST(TextureLod, EveryCameraPathFiltersTheChecker) {
  for (const char* integrator : {"bdpt", "vcm", "pm", "sppm"}) {
    SCOPED_TRACE(integrator);
    check_camera_side(false, integrator);
  }
}

// Through the mirror the photon mappers' visible points lie beyond a delta bounce.
TEST(TextureLod, PhotonMappersConeThroughAMirror) {
  for (const char* integrator : {"pm", "sppm"}) {
    SCOPED_TRACE(integrator);
    check_camera_side(true, integrator);
  }
}

}  // namespace
}  // namespace clpt::texture_lod_test
