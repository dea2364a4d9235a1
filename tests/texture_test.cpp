// Textures on the device (kernels/texture/texture.cl through tests/kernels/texture_test.cl):
// texel placement, bilinear and nearest filtering, the sRGB decode, the three wrap modes and
// the texture slot's UV set and transform; and the loader's KHR_texture_transform matrix.
// Mip maps: the levels host/render/mipmaps.cpp builds (sizes, means in linear light) and the
// kernel's trilinear lookup between them (TextureLod); the footprint end to end is in
// tests/texture_lod_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "render/mipmaps.h"
#include "render/scene_buffers.h"
#include "scene/scene.h"
#include "support/device.h"

namespace clpt::texture_test {
namespace {

const cl::Program& texture_program() {
  return test::test_program("kernels/texture_test.cl");
}

uint32_t rgba(uint32_t r, uint32_t g, uint32_t b, uint32_t a = 255) { return r | g << 8 | b << 16 | a << 24; }

// A scene of one triangle (the kernels need a BVH) plus the given textures and materials.
struct TextureScene {
  FlatScene flat;
  std::unique_ptr<SceneBuffers> buffers;
  explicit TextureScene(Scene scene) {
    scene.positions = {{0, 0, -10}, {1, 0, -10}, {0, 1, -10}};
    scene.normals.assign(3, glm::vec3(0.0f));
    scene.uvs.assign(3, glm::vec2(0.0f));
    scene.triangles = {{0, 1, 2}};
    if (scene.materials.empty()) scene.materials.emplace_back();
    scene.triangle_materials = {0};
    const Bvh bvh = build_bvh(scene.positions, scene.triangles);
    flat = flatten_scene(scene, bvh);
    buffers = std::make_unique<SceneBuffers>(test::device_context(), flat);
  }
};

Texture make_texture(uint32_t w, uint32_t h, std::vector<uint32_t> texels, Texture::Wrap ws = Texture::Wrap::Repeat,
                     Texture::Wrap wt = Texture::Wrap::Repeat, bool nearest = false) {
  Texture t;
  t.width = w;
  t.height = h;
  t.texels = std::move(texels);
  t.wrap_s = ws;
  t.wrap_t = wt;
  t.nearest = nearest;
  return t;
}

std::vector<glm::vec4> lookup(const TextureScene& ts, int texture, bool srgb, const std::vector<glm::vec2>& uv) {
  cl::Context& ctx = test::device_context();
  const uint32_t n = uint32_t(uv.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, uv);
  cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "texture lookups");
  cl::Kernel k(texture_program(), "texture_lookup");
  const cl_uint next = ts.buffers->bind(k, 0);
  k.args(next, int32_t(texture), uint32_t(srgb ? 1 : 0), in, out, n);
  k.launch(ctx, n);
  ctx.finish();
  return out.read_vector<glm::vec4>(n);
}

glm::vec4 unorm(uint32_t c) {
  return glm::vec4(c & 255u, (c >> 8) & 255u, (c >> 16) & 255u, c >> 24) / 255.0f;
}

#define EXPECT_VEC4_NEAR(a, b, tol)                                               \
  do {                                                                            \
    const glm::vec4 a_ = (a), b_ = (b);                                           \
    for (int c_ = 0; c_ < 4; ++c_) EXPECT_NEAR(a_[c_], b_[c_], (tol)) << "channel " << c_; \
  } while (0)

// A 4x2 texture with distinct texels: each texel centre returns that texel exactly (row 0 at
// v = 0), the midpoint of two neighbours their mean, the centre of four their mean; NEAREST
// returns the texel under the point.
TEST(Texture, TexelsLandWhereTheUvSays) {
  std::vector<uint32_t> texels(8);
  for (uint32_t j = 0; j < 2; ++j)
    for (uint32_t i = 0; i < 4; ++i) texels[j * 4 + i] = rgba(10 + 40 * i, 20 + 100 * j, 7 * (i + 4 * j), 255 - 30 * i);
  Scene scene;
  scene.textures.push_back(make_texture(4, 2, texels, Texture::Wrap::Clamp, Texture::Wrap::Clamp));
  scene.textures.push_back(make_texture(4, 2, texels, Texture::Wrap::Clamp, Texture::Wrap::Clamp, true));
  TextureScene ts(scene);
  std::vector<glm::vec2> uv;
  for (uint32_t j = 0; j < 2; ++j)
    for (uint32_t i = 0; i < 4; ++i) uv.push_back({(i + 0.5f) / 4.0f, (j + 0.5f) / 2.0f});
  uv.push_back({2.0f / 4.0f, 0.5f / 2.0f});  // between texels (1,0) and (2,0)
  uv.push_back({1.0f / 4.0f, 1.0f / 2.0f});  // between (0,0) (1,0) (0,1) (1,1)
  uv.push_back({0.3f, 0.7f});                // a bilinear point with weights 0.7 / 0.9
  const std::vector<glm::vec4> lin = lookup(ts, 0, false, uv);
  const std::vector<glm::vec4> near = lookup(ts, 1, false, uv);
  for (uint32_t k = 0; k < 8; ++k) {
    SCOPED_TRACE(k);
    EXPECT_VEC4_NEAR(lin[k], unorm(texels[k]), 1e-6f);
    EXPECT_VEC4_NEAR(near[k], unorm(texels[k]), 1e-6f);
  }
  EXPECT_VEC4_NEAR(lin[8], 0.5f * (unorm(texels[1]) + unorm(texels[2])), 1e-6f);
  EXPECT_VEC4_NEAR(lin[9], 0.25f * (unorm(texels[0]) + unorm(texels[1]) + unorm(texels[4]) + unorm(texels[5])), 1e-6f);
  // u = 0.3: x = 1.2 - 0.5 = 0.7 -> texels 0, 1 with weight 0.7 on 1; v = 0.7: y = 0.9 -> rows 0, 1.
  const glm::vec4 top = glm::mix(unorm(texels[0]), unorm(texels[1]), 0.7f);
  const glm::vec4 bottom = glm::mix(unorm(texels[4]), unorm(texels[5]), 0.7f);
  EXPECT_VEC4_NEAR(lin[10], glm::mix(top, bottom, 0.9f), 2e-6f);
  EXPECT_VEC4_NEAR(near[8], unorm(texels[2]), 1e-6f);   // x = 2.0: texel 2
  EXPECT_VEC4_NEAR(near[10], unorm(texels[5]), 1e-6f);  // x = 1.2, y = 1.4
}

double srgb_eotf(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// The sRGB decode: every 8-bit value through the table (nearest texel centres of a 256x1
// texture) and the formula at 0, the 0.04045 boundary, 0.5 and 1, against double precision.
TEST(Texture, SrgbDecode) {
  std::vector<uint32_t> texels(256);
  for (uint32_t k = 0; k < 256; ++k) texels[k] = rgba(k, k, k, k);
  Scene scene;
  scene.textures.push_back(make_texture(256, 1, texels, Texture::Wrap::Clamp, Texture::Wrap::Clamp, true));
  TextureScene ts(scene);
  std::vector<glm::vec2> uv;
  for (uint32_t k = 0; k < 256; ++k) uv.push_back({(k + 0.5f) / 256.0f, 0.5f});
  const std::vector<glm::vec4> got = lookup(ts, 0, true, uv);
  for (uint32_t k = 0; k < 256; ++k) {
    const double want = srgb_eotf(k / 255.0);
    EXPECT_NEAR(got[k].x, want, 1e-7 + 1e-6 * want) << k;
    EXPECT_NEAR(got[k].w, k / 255.0, 1e-7) << "alpha is linear, " << k;
  }
  EXPECT_EQ(got[0].x, 0.0f);
  EXPECT_EQ(got[255].x, 1.0f);
  // 10/255 is below the 0.04045 knee (linear segment), 11/255 above it (power segment).
  EXPECT_NEAR(got[10].x, 10.0 / 255.0 / 12.92, 1e-9);
  EXPECT_NEAR(got[11].x, std::pow((11.0 / 255.0 + 0.055) / 1.055, 2.4), 1e-8);

  cl::Context& ctx = test::device_context();
  const std::vector<float> in = {0.0f, 0.04045f, std::nextafter(0.04045f, 1.0f), 0.5f, 1.0f};
  cl::Buffer bin = cl::Buffer::from_vector(ctx, in);
  cl::Buffer bout(ctx, in.size() * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "srgb");
  cl::Kernel k(texture_program(), "srgb_formula");
  k.args(0, bin, bout, uint32_t(in.size()));
  k.launch(ctx, in.size());
  ctx.finish();
  const std::vector<float> out = bout.read_vector<float>(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const double want = srgb_eotf(double(in[i]));
    EXPECT_NEAR(out[i], want, 2e-7 + 2e-6 * want) << in[i];
  }
  EXPECT_NEAR(out[3], 0.214041140, 5e-7);  // sRGB 0.5
}

// Wrap modes along u on a 4x1 texture (texel i has red 10 i + 5), NEAREST so each lookup
// names one texel: repeat, clamp to edge and mirrored repeat, negative and large u included.
TEST(Texture, WrapModes) {
  std::vector<uint32_t> texels;
  for (uint32_t i = 0; i < 4; ++i) texels.push_back(rgba(10 * i + 5, 0, 0));
  Scene scene;
  for (Texture::Wrap w : {Texture::Wrap::Repeat, Texture::Wrap::Clamp, Texture::Wrap::Mirror})
    scene.textures.push_back(make_texture(4, 1, texels, w, Texture::Wrap::Repeat, true));
  // Bilinear with wrap: at u = 0 (the left edge) the filter mixes texel 0 with the texel the
  // mode puts left of it.
  for (Texture::Wrap w : {Texture::Wrap::Repeat, Texture::Wrap::Clamp, Texture::Wrap::Mirror})
    scene.textures.push_back(make_texture(4, 1, texels, w, Texture::Wrap::Repeat, false));
  TextureScene ts(scene);
  // u at texel centres k + 0.5 for k in -6..9.
  std::vector<glm::vec2> uv;
  for (int k = -6; k <= 9; ++k) uv.push_back({(k + 0.5f) / 4.0f, 0.5f});
  const int repeat[] = {2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1};
  const int clamp[] = {0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3, 3};
  const int mirror[] = {2, 3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1};
  const int* want[] = {repeat, clamp, mirror};
  for (int mode = 0; mode < 3; ++mode) {
    const std::vector<glm::vec4> got = lookup(ts, mode, false, uv);
    for (size_t i = 0; i < uv.size(); ++i)
      EXPECT_NEAR(got[i].x * 255.0f, 10.0f * want[mode][i] + 5.0f, 1e-3f) << "mode " << mode << " u " << uv[i].x;
  }
  const std::vector<glm::vec2> edge = {{0.0f, 0.5f}, {-1e9f, 0.5f}, {std::nanf(""), 0.5f}};
  const float left[] = {(5.0f + 35.0f) / 2.0f, 5.0f, 5.0f};  // repeat: texels 3 and 0; clamp, mirror: 0
  for (int mode = 0; mode < 3; ++mode) {
    const std::vector<glm::vec4> got = lookup(ts, 3 + mode, false, edge);
    EXPECT_NEAR(got[0].x * 255.0f, left[mode], 1e-3f) << "mode " << mode;
    for (const glm::vec4& g : got) EXPECT_TRUE(std::isfinite(g.x)) << "mode " << mode;
  }
}

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv on the UV set the slot names.
TEST(Texture, SlotTransformAndTexCoord) {
  const double ox = 0.25, oy = -0.5, rot = 0.3, sx = 2.0, sy = 3.0;
  // Hand-built 3x3 matrices as the extension's README writes them (row-major).
  const double T[3][3] = {{1, 0, ox}, {0, 1, oy}, {0, 0, 1}};
  const double R[3][3] = {{std::cos(rot), std::sin(rot), 0}, {-std::sin(rot), std::cos(rot), 0}, {0, 0, 1}};
  const double S[3][3] = {{sx, 0, 0}, {0, sy, 0}, {0, 0, 1}};
  double TR[3][3] = {}, M[3][3] = {};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) TR[r][c] += T[r][k] * R[k][c];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) M[r][c] += TR[r][k] * S[k][c];
  Scene scene;
  Material m;
  m.base_color_texture.texture = 0;
  m.base_color_texture.texcoord = 1;
  m.base_color_texture.transform = glm::mat3x2(glm::vec2(M[0][0], M[1][0]), glm::vec2(M[0][1], M[1][1]),
                                               glm::vec2(M[0][2], M[1][2]));
  m.emissive_texture.texture = 0;  // identity, UV set 0
  scene.materials.push_back(m);
  scene.textures.push_back(make_texture(1, 1, {rgba(1, 2, 3)}));
  TextureScene ts(scene);
  const std::vector<glm::vec4> uvs = {{0.1f, 0.2f, 0.7f, -0.4f}, {5.0f, -3.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f, 1.0f}};
  cl::Context& ctx = test::device_context();
  auto run = [&](uint32_t slot) {
    cl::Buffer in = cl::Buffer::from_vector(ctx, uvs);
    cl::Buffer out(ctx, uvs.size() * sizeof(glm::vec2), CL_MEM_WRITE_ONLY, nullptr, "uv");
    cl::Kernel k(texture_program(), "slot_uv");
    const cl_uint next = ts.buffers->bind(k, 0);
    k.args(next, uint32_t(0), slot, in, out, uint32_t(uvs.size()));
    k.launch(ctx, uvs.size());
    ctx.finish();
    return out.read_vector<glm::vec2>(uvs.size());
  };
  const std::vector<glm::vec2> base = run(dev::TEX_BASE_COLOR), emissive = run(dev::TEX_EMISSIVE);
  for (size_t i = 0; i < uvs.size(); ++i) {
    const double u = uvs[i].z, v = uvs[i].w;  // texCoord 1
    EXPECT_NEAR(base[i].x, M[0][0] * u + M[0][1] * v + M[0][2], 1e-5) << i;
    EXPECT_NEAR(base[i].y, M[1][0] * u + M[1][1] * v + M[1][2], 1e-5) << i;
    EXPECT_EQ(emissive[i].x, uvs[i].x) << i;
    EXPECT_EQ(emissive[i].y, uvs[i].y) << i;
  }
}

// The mip chain of a 5 x 3 image: 2 x 1, then 1 x 1 (3 levels); each texel the mean of the
// texels it covers (2 or 3 per axis), sRGB images averaged in linear light: black and white
// give sRGB 188 (linear 0.5), not 128.
TEST(Mipmaps, LevelsAverageInLinearLight) {
  std::vector<uint32_t> texels(15);
  for (uint32_t j = 0; j < 3; ++j)
    for (uint32_t i = 0; i < 5; ++i) texels[j * 5 + i] = (i + j) % 2 ? rgba(255, 255, 255, 255) : rgba(0, 99, 0, 0);
  uint32_t levels = 0;
  const std::vector<uint32_t> lin = build_mip_levels(texels, 5, 3, false, &levels);
  EXPECT_EQ(levels, 3u);
  ASSERT_EQ(lin.size(), 2u + 1u);
  // Level 1 texel 0 covers x 0-1, y 0-2 (6 texels: 3 white); texel 1 covers x 2-4 (9: 4 white).
  auto mean = [](double white, double n, double other) { return uint32_t(std::lround((white * 255.0 + (n - white) * other) / n)); };
  EXPECT_EQ(lin[0] & 255u, mean(3, 6, 0));
  EXPECT_EQ((lin[0] >> 8) & 255u, mean(3, 6, 99));
  EXPECT_EQ(lin[0] >> 24, mean(3, 6, 0));
  EXPECT_EQ(lin[1] & 255u, mean(4, 9, 0));
  // Level 2: the mean of level 1's two texels.
  EXPECT_EQ(lin[2] & 255u, uint32_t(std::lround(0.5 * ((lin[0] & 255u) + (lin[1] & 255u)))));
  // sRGB: a 2 x 2 checker of black and white is linear 0.5, sRGB 0.7354 = 188 / 255; alpha
  // (here 255 and 0) is averaged as it is, 128.
  const std::vector<uint32_t> checker = {rgba(0, 0, 0, 0), rgba(255, 255, 255, 255), rgba(255, 255, 255, 255),
                                         rgba(0, 0, 0, 0)};
  const std::vector<uint32_t> srgb = build_mip_levels(checker, 2, 2, true, &levels);
  EXPECT_EQ(levels, 2u);
  ASSERT_EQ(srgb.size(), 1u);
  EXPECT_EQ(srgb[0] & 255u, 188u);
  EXPECT_EQ(srgb[0] >> 24, 128u);
  // A 1 x 1 image has no levels below it; a 16384 x 1 one has 15.
  EXPECT_TRUE(build_mip_levels({rgba(1, 2, 3)}, 1, 1, false, &levels).empty());
  EXPECT_EQ(levels, 1u);
  EXPECT_EQ(build_mip_levels(std::vector<uint32_t>(16384, 0u), 16384, 1, false, &levels).size(), 16383u);
  EXPECT_EQ(levels, 15u);
}

// Only colour slots make a texture sRGB for its mip chain.
TEST(Mipmaps, SrgbFromTheSlotsThatReadATexture) {
  Scene scene;
  scene.textures.resize(3);
  Material m;
  m.base_color_texture.texture = 0;
  m.metallic_roughness_texture.texture = 1;
  m.normal_texture.texture = 2;
  m.sheen_color_texture.texture = 2;  // read by a colour slot too: sRGB
  scene.materials.push_back(m);
  const std::vector<bool> srgb = textures_read_as_srgb(scene);
  EXPECT_EQ(srgb, (std::vector<bool>{true, false, true}));
}

// The kernel's levels: lambda <= 0 is the bilinear lookup of level 0 (the same value as
// texture_sample); lambda 1 and 2 read levels 1 and 2 (uniform there: the checker's mean);
// lambda 0.5 is halfway between level 0's bilinear value and level 1's; lambda past the
// last level stays at the 1 x 1 level.
TEST(TextureLod, TrilinearBetweenLevels) {
  std::vector<uint32_t> texels(16);
  for (uint32_t j = 0; j < 4; ++j)
    for (uint32_t i = 0; i < 4; ++i) texels[j * 4 + i] = (i + j) % 2 ? rgba(200, 40, 0) : rgba(0, 40, 200);
  Scene scene;
  scene.textures.push_back(make_texture(4, 4, texels));
  TextureScene ts(scene);
  const glm::vec2 at(0.375f, 0.125f);  // texel (1, 0)'s centre: level 0 reads texel (1, 0) alone
  const std::vector<glm::vec4> q = {{at, -1.0f, 0}, {at, 0.0f, 0}, {at, 1.0f, 0}, {at, 2.0f, 0},
                                    {at, 0.5f, 0},  {at, 7.0f, 0}};
  cl::Context& ctx = test::device_context();
  cl::Buffer in = cl::Buffer::from_vector(ctx, q);
  cl::Buffer out(ctx, q.size() * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "lod lookups");
  cl::Kernel k(texture_program(), "texture_lookup_lod");
  const cl_uint next = ts.buffers->bind(k, 0);
  k.args(next, int32_t(0), uint32_t(0), in, out, uint32_t(q.size()));
  k.launch(ctx, q.size());
  ctx.finish();
  const std::vector<glm::vec4> got = out.read_vector<glm::vec4>(q.size());
  const glm::vec4 l0 = unorm(texels[1]), mid = unorm(rgba(100, 40, 100));
  EXPECT_VEC4_NEAR(got[0], l0, 1e-6f);
  EXPECT_VEC4_NEAR(got[1], l0, 1e-6f);
  EXPECT_VEC4_NEAR(got[2], mid, 1e-6f);
  EXPECT_VEC4_NEAR(got[3], mid, 1e-6f);
  EXPECT_VEC4_NEAR(got[4], 0.5f * (l0 + mid), 1e-6f);
  EXPECT_VEC4_NEAR(got[5], mid, 1e-6f);
  EXPECT_EQ(ts.flat.mip_texels, 4u + 1u);
  EXPECT_EQ((ts.flat.textures[0].flags >> dev::TEXTURE_LEVELS_SHIFT) & 31u, 3u);
}

}  // namespace
}  // namespace clpt::texture_test
