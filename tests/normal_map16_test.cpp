// 16-bit normal maps (issue 22): a 16-bit PNG read only as a normal map keeps its 16 bits from
// the decoder through the texel buffer (Texture::wide, dev::TEXTURE_WIDE) and its mip levels to
// the kernels' lookup, where an 8-bit one is rounded to steps of 1/127 in a normal's components;
// a 16-bit image any other slot reads is rounded to 8 bits, as before.
//
// The normal map is one texel, (32805, 32768, 65535) / 65535: a tangent-space normal tilted by
// 0.00114 towards +x. Rounded to 8 bits (128, 128, 255) the tilt would be 0.00392.
#include <gtest/gtest.h>


#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/png_codec.h"
#include "render/aov.h"
#include "render/mipmaps.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "support/gltf_square.h"
#include "support/scenes.h"
#include "util/log.h"

namespace clpt::normal_map16_test {
namespace {

namespace fs = std::filesystem;

constexpr uint16_t kTexel[3] = {32805, 32768, 65535};

// The tangent-space normal's x over its length, from channels in [0, 1].
double tilt(double r, double g, double b) {
  const double x = 2.0 * r - 1.0, y = 2.0 * g - 1.0, z = 2.0 * b - 1.0;
  return x / std::sqrt(x * x + y * y + z * z);
}

const double kTilt16 = tilt(kTexel[0] / 65535.0, kTexel[1] / 65535.0, kTexel[2] / 65535.0);
const double kTilt8 = tilt(128 / 255.0, 128 / 255.0, 1.0);

// The square of support/gltf_square.h with `material`, its image 0 a 16-bit PNG of kTexel.
Scene square_with_16bit_image(const std::string& tag, const nlohmann::json& material, const LoadOptions& options = {}) {
  const fs::path file = test::write_square("normal16-" + tag, material, {}, {{"n.png", {128, 128, 255}}});
  const fs::path png = file.parent_path() / "n.png";  // written over with 16 bits a channel
  std::string why;
  EXPECT_TRUE(write_png(png, 1, 1, 3, 16, kTexel, {}, &why)) << why;
  log::set_level(log::Level::Quiet);
  Scene scene = load_gltf(file, options);
  fs::remove_all(file.parent_path());
  return scene;
}

const nlohmann::json kLambert = {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"metallicFactor", 0.0}};

TEST(NormalMap16, TheLoaderKeepsSixteenBitsForANormalMap) {
  const Scene scene = square_with_16bit_image("loader", {{"pbrMetallicRoughness", kLambert}, {"normalTexture", {{"index", 0}}}});
  ASSERT_EQ(scene.textures.size(), 1u);
  const Texture& t = scene.textures[0];
  EXPECT_TRUE(t.wide);
  ASSERT_EQ(t.texels.size(), 2u);
  EXPECT_EQ(t.texels[0], uint32_t(kTexel[0]) | uint32_t(kTexel[1]) << 16);
  EXPECT_EQ(t.texels[1], uint32_t(kTexel[2]) | 65535u << 16) << "no alpha: opaque";
  EXPECT_EQ(t.rgba8(0), 128u | 128u << 8 | 255u << 16 | 255u << 24);
}

TEST(NormalMap16, OtherSlotsGetEightBits) {
  // Base colour alone, and the same texture as base colour and normal map: 8 bits.
  for (const bool also_normal : {false, true}) {
    SCOPED_TRACE(also_normal ? "base colour and normal map" : "base colour");
    nlohmann::json pbr = kLambert;
    pbr["baseColorTexture"] = {{"index", 0}};
    nlohmann::json material = {{"pbrMetallicRoughness", pbr}};
    if (also_normal) material["normalTexture"] = {{"index", 0}};
    const Scene scene = square_with_16bit_image(also_normal ? "both" : "colour", material);
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_FALSE(scene.textures[0].wide);
    ASSERT_EQ(scene.textures[0].texels.size(), 1u);
    EXPECT_EQ(scene.textures[0].texels[0], 128u | 128u << 8 | 255u << 16 | 255u << 24);
  }
}

// --limit total-texels counts a 16-bit texel twice (it takes two words): with room for one
// texel the 1x1 normal map is kept at 8 bits, with room for two at 16.
TEST(NormalMap16, ASixteenBitTexelCountsTwiceAgainstTheLimit) {
  const nlohmann::json material = {{"pbrMetallicRoughness", kLambert}, {"normalTexture", {{"index", 0}}}};
  for (const uint64_t limit : {1u, 2u}) {
    SCOPED_TRACE(limit);
    LoadOptions options;
    options.limits.total_texels = limit;
    const Scene scene = square_with_16bit_image("limit" + std::to_string(limit), material, options);
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].wide, limit == 2u);
    ASSERT_EQ(scene.textures[0].texels.size(), limit == 2u ? 2u : 1u);
    if (limit == 1u) {
      EXPECT_EQ(scene.textures[0].texels[0], 128u | 128u << 8 | 255u << 16 | 255u << 24);
    }
  }
}

// The kernels read the 16 bits: the normal AOV (the shading normal, normal map included) of
// the square seen head-on has the 16-bit tilt, to float precision, at every pixel, with and
// without mip levels.
TEST(NormalMap16, TheKernelsReadSixteenBits) {
  Scene scene = square_with_16bit_image("kernel", {{"pbrMetallicRoughness", kLambert}, {"normalTexture", {{"index", 0}}}});
  test::add_camera_on_z(scene, 2.0f, 1.0f);
  for (const bool mipmaps : {true, false}) {
    SCOPED_TRACE(mipmaps ? "trilinear" : "bilinear");
    RenderSettings s;
    s.integrator = "ao";
    s.width = s.height = 8;
    s.spp = 2;
    s.aovs = AOV_NORMAL;
    s.mipmaps = mipmaps;
    const RenderOutput out = Renderer(test::device_context(), scene, s).render();
    ASSERT_EQ(out.aovs.size(), 1u);
    const Image& n = out.aovs[0].image;
    double worst = 0.0;
    for (size_t i = 0; i < size_t(n.width) * n.height; ++i) worst = std::max(worst, std::fabs(n.rgb[3 * i] - kTilt16));
    EXPECT_LT(worst, 2e-5) << "16-bit tilt " << kTilt16 << ", 8-bit " << kTilt8 << ", pixel 0 " << n.rgb[0];
  }
}

// Mip levels of a wide texture are averaged at 16 bits: two texels 32805 and 32808 make
// 32807 (32806.5 rounded), which 8 bits cannot tell from 128 * 257.
TEST(NormalMap16, MipLevelsKeepSixteenBits) {
  const std::vector<uint32_t> texels = {32805u | 32768u << 16, 65535u | 65535u << 16,
                                        32808u | 32768u << 16, 65535u | 65535u << 16};
  uint32_t levels = 0;
  const std::vector<uint32_t> mips = build_mip_levels(texels, 2, 1, false, &levels, true);
  EXPECT_EQ(levels, 2u);
  ASSERT_EQ(mips.size(), 2u);
  EXPECT_EQ(mips[0], 32807u | 32768u << 16);
  EXPECT_EQ(mips[1], 65535u | 65535u << 16);
}

}  // namespace
}  // namespace clpt::normal_map16_test
