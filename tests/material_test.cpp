// Materials on the device (kernels/material/material.cl, material/alpha.cl through
// tests/kernels/texture_test.cl) and tangent generation (host/scene/tangents.cpp):
// TEXCOORD_1 and COLOR_0 reach the BSDF inputs, textures multiply the factors, emission with
// its texture, the normal map's shading normal, alpha MASK and BLEND in both traversals.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "render/scene_buffers.h"
#include "scene/scene.h"
#include "scene/tangents.h"
#include "support/device.h"

namespace clpt::material_test {
namespace {

const cl::Program& material_program() {
  return test::test_program("kernels/texture_test.cl");
}

uint32_t rgba(uint32_t r, uint32_t g, uint32_t b, uint32_t a = 255) { return r | g << 8 | b << 16 | a << 24; }

double srgb_eotf(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// The unit quad [0,1]^2 at z = 0 facing +z, as two triangles: vertex k at corner (x, y) has
// glTF UV (x, 1 - y) (image row 0 at the top), TEXCOORD_1 (y, x) and the colour given.
Scene quad_scene(const Material& m, std::vector<Texture> textures, bool extra = true,
                 glm::vec4 tangent = glm::vec4(1, 0, 0, 1)) {
  Scene s;
  const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    const glm::vec2 c = corners[k];
    s.positions.push_back(glm::vec3(c, 0.0f));
    s.normals.push_back(glm::vec3(0, 0, 1));
    s.uvs.push_back(glm::vec2(c.x, 1.0f - c.y));
    if (extra) {
      s.uvs1.push_back(glm::vec2(c.y, c.x));
      s.colors.push_back(glm::vec4(0.5f + 0.5f * c.x, 1.0f, 0.25f, 0.8f));
      s.tangents.push_back(tangent);
    }
  }
  s.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.triangle_materials = {0, 0};
  s.materials.push_back(m);
  s.textures = std::move(textures);
  return s;
}

struct DeviceScene {
  FlatScene flat;
  std::unique_ptr<SceneBuffers> buffers;
  explicit DeviceScene(const Scene& scene) {
    const Bvh bvh = build_bvh(scene.positions, scene.triangles);
    flat = flatten_scene(scene, bvh);
    buffers = std::make_unique<SceneBuffers>(test::device_context(), flat);
  }
};

struct Resolved {
  glm::vec4 hit, base, ns, emission, emission_at;
};

// Runs texture_test.cl's `kernel` (scene, origins, directions, out, n) over rays straight
// down -z from the origins given; per_ray values of T come back for each ray.
template <typename T>
std::vector<T> launch_down_rays(const DeviceScene& ds, const char* kernel,
                                const std::vector<glm::vec4>& org, size_t per_ray, const char* what) {
  cl::Context& ctx = test::device_context();
  const std::vector<glm::vec4> dir(org.size(), glm::vec4(0, 0, -1, 0));
  const uint32_t n = uint32_t(org.size());
  cl::Buffer bo = cl::Buffer::from_vector(ctx, org), bd = cl::Buffer::from_vector(ctx, dir);
  cl::Buffer out(ctx, per_ray * n * sizeof(T), CL_MEM_WRITE_ONLY, nullptr, what);
  cl::Kernel k(material_program(), kernel);
  const cl_uint next = ds.buffers->bind(k, 0);
  k.args(next, bo, bd, out, n);
  k.launch(ctx, n);
  ctx.finish();
  return out.read_vector<T>(per_ray * n);
}

// Origins at height 1 above the quad's points (x, y).
std::vector<glm::vec4> above(const std::vector<glm::vec2>& xy) {
  std::vector<glm::vec4> org;
  for (glm::vec2 p : xy) org.emplace_back(p, 1.0f, 0.0f);
  return org;
}

// Rays straight down -z onto the quad at the given (x, y).
std::vector<Resolved> resolve(const DeviceScene& ds, const std::vector<glm::vec2>& xy) {
  return launch_down_rays<Resolved>(ds, "resolve_rays", above(xy), 1, "resolved");
}

Texture texture(uint32_t w, uint32_t h, std::vector<uint32_t> texels, bool nearest = true) {
  Texture t;
  t.width = w;
  t.height = h;
  t.texels = std::move(texels);
  t.nearest = nearest;
  t.wrap_s = t.wrap_t = Texture::Wrap::Clamp;
  return t;
}

// Base colour = factor x sRGB texture (on TEXCOORD_1) x COLOR_0; metallic (B) and roughness
// (G) from their texture; emission = factor x sRGB emissive texture, equal to what
// material_emission_at gives for the same point.
TEST(Material, ResolveReadsTexturesUv1AndColor) {
  Material m;
  m.base_color = glm::vec4(0.5f, 1.0f, 0.8f, 1.0f);
  m.metallic = 0.5f;
  m.roughness = 0.8f;
  m.emission = glm::vec3(2.0f, 3.0f, 4.0f);
  m.base_color_texture.texture = 0;
  m.base_color_texture.texcoord = 1;   // TEXCOORD_1 = (y, x): left/right texel by y
  m.metallic_roughness_texture.texture = 1;
  m.emissive_texture.texture = 2;      // TEXCOORD_0 = (x, 1 - y): left/right by x
  const uint32_t left = rgba(200, 100, 50), right = rgba(20, 240, 128);
  Scene s = quad_scene(m, {texture(2, 1, {left, right}), texture(1, 1, {rgba(0, 51, 204)}),
                           texture(2, 1, {rgba(255, 0, 128), rgba(64, 64, 64)})});
  DeviceScene ds(s);
  const std::vector<glm::vec2> pts = {{0.2f, 0.3f}, {0.7f, 0.9f}, {0.9f, 0.1f}};
  const std::vector<Resolved> r = resolve(ds, pts);
  for (size_t i = 0; i < pts.size(); ++i) {
    SCOPED_TRACE(i);
    const glm::vec2 p = pts[i];
    ASSERT_EQ(r[i].hit.x, 1.0f);
    EXPECT_NEAR(r[i].hit.z, p.y, 1e-5f);  // uv1 = (y, x)
    EXPECT_NEAR(r[i].hit.w, p.x, 1e-5f);
    const uint32_t t = p.y < 0.5f ? left : right;
    const glm::vec3 color(0.5f + 0.5f * p.x, 1.0f, 0.25f);
    for (int c = 0; c < 3; ++c) {
      const double tex = srgb_eotf(((t >> (8 * c)) & 255u) / 255.0);
      EXPECT_NEAR(r[i].base[c], m.base_color[c] * tex * color[c], 2e-5) << "channel " << c;
    }
    EXPECT_NEAR(r[i].base.w, 0.5 * 204.0 / 255.0, 1e-6);  // metallic x B
    EXPECT_NEAR(r[i].ns.w, 0.8 * 51.0 / 255.0, 1e-6);     // roughness x G
    EXPECT_NEAR(r[i].emission_at.w, 0.8f, 1e-6f);         // COLOR_0 alpha
    const uint32_t e = p.x < 0.5f ? rgba(255, 0, 128) : rgba(64, 64, 64);
    for (int c = 0; c < 3; ++c) {
      const double want = m.emission[c] * srgb_eotf(((e >> (8 * c)) & 255u) / 255.0);
      EXPECT_NEAR(r[i].emission[c], want, 1e-5 + 1e-6 * want) << "channel " << c;
      EXPECT_NEAR(r[i].emission_at[c], r[i].emission[c], 1e-6f) << "channel " << c;
    }
  }
}

// The plain material's shortcut (material_resolve_plain) against the general resolve: for
// materials with neither textures nor layers, every BSDF input, the shading normal and the
// emission are the same bit for bit, with and without COLOR_0 (which multiplies the base
// colour); the host flags exactly those materials MATERIAL_PLAIN, and one texture or one
// layer clears the flag.
std::vector<int> resolve_plain_both(const DeviceScene& ds, const std::vector<glm::vec2>& xy) {
  return launch_down_rays<int>(ds, "resolve_plain_both", above(xy), 2, "plain and full");
}

TEST(Material, ResolvePlainIsResolveFull) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::vector<glm::vec2> pts = {{0.2f, 0.3f}, {0.7f, 0.9f}, {0.9f, 0.1f}, {0.5f, 0.5f}};
  for (int i = 0; i < 24; ++i) {
    Material m;
    m.base_color = glm::vec4(u(rng), u(rng), u(rng), u(rng));
    m.metallic = i % 3 == 0 ? 0.0f : u(rng);
    m.roughness = u(rng);
    m.transmission = i % 2 == 0 ? 0.0f : u(rng);
    m.dispersion = i % 4 < 2 ? 0.0f : 20.0f / (20.0f + 40.0f * u(rng));
    m.ior = 1.0f + u(rng);
    m.specular = u(rng);
    m.specular_color = glm::vec3(u(rng), u(rng), u(rng));
    m.diffuse_transmission_color = glm::vec3(u(rng), u(rng), u(rng));
    m.iridescence_ior = 1.0f + u(rng);
    m.iridescence_thickness_max = 100.0f + 500.0f * u(rng);
    if (i % 5 == 0) m.emission = glm::vec3(u(rng), 2.0f * u(rng), 0.0f);
    const bool extra = i % 2 == 0;  // COLOR_0 (with TEXCOORD_1 and tangents) or none
    SCOPED_TRACE(testing::Message() << "material " << i << " extra " << extra);
    DeviceScene ds(quad_scene(m, {}, extra));
    const std::vector<int> r = resolve_plain_both(ds, pts);
    for (size_t k = 0; k < pts.size(); ++k) {
      EXPECT_EQ(r[2 * k], 0) << "point " << k << ": fields that differ (bit = field)";
      EXPECT_EQ(r[2 * k + 1], 1) << "point " << k << ": not flagged plain";
    }
  }
  // One texture, or one layer, and the material takes the general path.
  std::vector<std::pair<const char*, Material>> not_plain;
  auto add = [&](const char* what, auto set) {
    Material m;
    set(m);
    not_plain.emplace_back(what, m);
  };
  add("base colour texture", [](Material& m) { m.base_color_texture.texture = 0; });
  add("emissive texture", [](Material& m) {
    m.emission = glm::vec3(1.0f);
    m.emissive_texture.texture = 0;
  });
  add("clearcoat normal texture only", [](Material& m) { m.clearcoat_normal_texture.texture = 0; });
  add("clearcoat", [](Material& m) { m.clearcoat = 0.5f; });
  add("iridescence", [](Material& m) { m.iridescence = 0.5f; });
  add("diffuse transmission", [](Material& m) { m.diffuse_transmission = 0.5f; });
  add("sheen", [](Material& m) { m.sheen_color = glm::vec3(0.0f, 0.0f, 0.25f); });
  add("anisotropy", [](Material& m) { m.anisotropy_strength = 0.5f; });
  for (const auto& [what, m] : not_plain) {
    SCOPED_TRACE(what);
    DeviceScene ds(quad_scene(m, {texture(1, 1, {rgba(10, 200, 30)})}));
    const std::vector<int> r = resolve_plain_both(ds, {{0.3f, 0.6f}});
    ASSERT_GE(r[0], 0) << "no hit";
    EXPECT_EQ(r[1], 0) << "flagged plain";
  }
}

// Normal map: texel (x, y, z) in [0, 1] -> n = (2c - 1) with xy scaled, in the frame
// (tangent, sign x cross(n, t), n). The quad's normal is +z, its tangent +x.
TEST(Material, NormalMapGivesExpectedShadingNormal) {
  auto encode = [](glm::vec3 n) {
    const glm::uvec3 q = glm::uvec3(glm::round((n * 0.5f + 0.5f) * 255.0f));
    return rgba(q.x, q.y, q.z);
  };
  auto decoded = [](uint32_t c) {
    return glm::vec3(c & 255u, (c >> 8) & 255u, (c >> 16) & 255u) / 255.0f * 2.0f - 1.0f;
  };
  struct Case {
    glm::vec3 map;
    float scale;
    glm::vec4 tangent;
    bool extra;
  };
  const Case cases[] = {
      {{0.6f, 0.0f, 0.8f}, 1.0f, {1, 0, 0, 1}, true},
      {{0.0f, 0.6f, 0.8f}, 1.0f, {1, 0, 0, 1}, true},    // bitangent cross(z, x) = +y
      {{0.0f, 0.6f, 0.8f}, 1.0f, {1, 0, 0, -1}, true},   // handedness -1: -y
      {{0.0f, 0.6f, 0.8f}, 1.0f, {0, 1, 0, 1}, true},    // tangent +y: bitangent -x
      {{0.6f, 0.0f, 0.8f}, 0.5f, {1, 0, 0, 1}, true},    // normal_scale on xy
      {{0.6f, 0.0f, 0.8f}, 1.0f, {0, 0, 0, 0}, true},    // no tangent: unchanged
      {{0.6f, 0.0f, 0.8f}, 1.0f, {0, 0, 0, 0}, false},   // no vertex attributes at all
      {{0.99f, 0.0f, -0.14f}, 1.0f, {1, 0, 0, 1}, true}, // below the surface: lifted above it
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(testing::Message() << "map " << c.map.x << "," << c.map.y << "," << c.map.z << " scale "
                                    << c.scale << " tangent " << c.tangent.x << "," << c.tangent.y << " w "
                                    << c.tangent.w << " extra " << c.extra);
    Material m;
    m.normal_texture.texture = 0;
    m.normal_scale = c.scale;
    const uint32_t texel = encode(c.map);
    Scene s = quad_scene(m, {texture(1, 1, {texel})}, c.extra, c.tangent);
    DeviceScene ds(s);
    const std::vector<Resolved> r = resolve(ds, {{0.3f, 0.6f}});
    ASSERT_EQ(r[0].hit.x, 1.0f);
    glm::vec3 want(0, 0, 1);
    if (c.extra && c.tangent != glm::vec4(0.0f)) {
      glm::vec3 d = decoded(texel);
      d.x *= c.scale;
      d.y *= c.scale;
      const glm::vec3 n(0, 0, 1), t(c.tangent), b = c.tangent.w * glm::cross(n, t);
      want = glm::normalize(d.x * t + d.y * b + d.z * n);
      if (want.z < 1e-3f) want = glm::normalize(want + (1e-3f - want.z) * n);
    }
    const glm::vec3 got(r[0].ns);
    EXPECT_NEAR(glm::length(got), 1.0f, 1e-5f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-5f) << "component " << k;
    EXPECT_GT(got.z, 0.0f);
  }
}

// Alpha rays: many rays down -z from distinct points over the quad.
std::vector<int> alpha_rays(const DeviceScene& ds, const std::vector<glm::vec4>& org) {
  return launch_down_rays<int>(ds, "alpha_rays", org, 2, "alpha hits");
}

// MASK: alpha = factor alpha x texture alpha x COLOR_0 alpha (0.8); the left half of the
// texture has alpha 0.25 (x 0.8 x 0.9 = 0.18 < 0.5: a hole), the right half 1 (0.72: solid).
TEST(Material, AlphaMaskHidesBelowCutoff) {
  Material m;
  m.alpha_mode = Material::AlphaMode::Mask;
  m.alpha_cutoff = 0.5f;
  m.base_color.w = 0.9f;
  m.base_color_texture.texture = 0;
  Scene s = quad_scene(m, {texture(2, 1, {rgba(255, 255, 255, 64), rgba(255, 255, 255, 255)})});
  DeviceScene ds(s);
  std::vector<glm::vec4> org;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) org.emplace_back((i + 0.5f) / 20.0f, (j + 0.5f) / 20.0f, 1.0f, 0.0f);
  const std::vector<int> hits = alpha_rays(ds, org);
  for (size_t i = 0; i < org.size(); ++i) {
    const int want = org[i].x > 0.5f ? 1 : 0;
    EXPECT_EQ(hits[2 * i], want) << "closest hit at x " << org[i].x;
    EXPECT_EQ(hits[2 * i + 1], want) << "any hit at x " << org[i].x;
  }
  // Cutoff above the solid side's alpha (0.72): everything is a hole.
  s.materials[0].alpha_cutoff = 0.75f;
  DeviceScene ds2(s);
  const std::vector<int> none = alpha_rays(ds2, org);
  for (int h : none) EXPECT_EQ(h, 0);
}

// BLEND: a fraction 1 - alpha of rays passes (binomial z-test, |z| < 4: p ~ 6e-5 per check);
// the closest-hit and any-hit traversals agree ray by ray, and a repeated ray gets the same
// answer. Opaque: every ray hits.
TEST(Material, AlphaBlendPassesFractionOneMinusAlpha) {
  for (float alpha : {0.3f, 0.75f}) {
    SCOPED_TRACE(alpha);
    Material m;
    m.alpha_mode = Material::AlphaMode::Blend;
    m.base_color.w = alpha / 0.8f;  // x COLOR_0 alpha 0.8
    Scene s = quad_scene(m, {});
    DeviceScene ds(s);
    std::vector<glm::vec4> org;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      // A scrambled grid of origins (R2 sequence) over the quad.
      const double x = std::fmod(0.5 + i * 0.7548776662466927, 1.0), y = std::fmod(0.5 + i * 0.5698402909980532, 1.0);
      org.emplace_back(float(0.02 + 0.96 * x), float(0.02 + 0.96 * y), 1.0f, 0.0f);
    }
    org.push_back(org[17]);  // the same ray twice
    const std::vector<int> hits = alpha_rays(ds, org);
    long k = 0, disagree = 0;
    for (int i = 0; i < n; ++i) {
      k += hits[2 * i];
      disagree += hits[2 * i] != hits[2 * i + 1];
    }
    EXPECT_EQ(disagree, 0);
    EXPECT_EQ(hits[2 * n], hits[2 * 17]);
    const double p = alpha, z = (k - n * p) / std::sqrt(n * p * (1 - p));
    EXPECT_LT(std::fabs(z), 4.0) << k << " of " << n << " rays hit, expected " << n * p;
  }
  Material opaque;
  opaque.base_color.w = 0.1f;  // ignored without an alpha mode
  DeviceScene ds(quad_scene(opaque, {}));
  const std::vector<int> hits = alpha_rays(ds, {{0.5f, 0.5f, 1.0f, 0.0f}, {0.2f, 0.7f, 1.0f, 0.0f}});
  for (int h : hits) EXPECT_EQ(h, 1);
}

// Tangents of a quad with known UVs: u along +x gives tangent +x; v increasing downwards
// (glTF) gives w = +1 (bitangent cross(n, t) = +y = decreasing v); a mirrored v gives -1, a
// mirrored u tangent -x; degenerate UVs give zero tangents.
TEST(Tangents, QuadWithKnownUvs) {
  const std::vector<glm::vec3> p = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  const std::vector<glm::uvec3> tris = {{0, 1, 2}, {0, 2, 3}};
  const std::vector<glm::vec3> n(4, glm::vec3(0, 0, 1));
  struct Case {
    std::vector<glm::vec2> uv;
    glm::vec4 want;
  };
  const Case cases[] = {
      {{{0, 1}, {1, 1}, {1, 0}, {0, 0}}, {1, 0, 0, 1}},    // glTF convention: v = 1 - y
      {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {1, 0, 0, -1}},   // v = y: mirrored
      {{{1, 1}, {0, 1}, {0, 0}, {1, 0}}, {-1, 0, 0, -1}},  // u = 1 - x, v = 1 - y
      {{{0, 0}, {0, 1}, {1, 1}, {1, 0}}, {0, 1, 0, 1}},    // u = y, v = x / 2: rotated
  };
  for (const Case& c : cases) {
    for (bool with_normals : {true, false}) {
      const std::vector<glm::vec4> t = generate_tangents(p, with_normals ? n : std::vector<glm::vec3>{}, c.uv, tris);
      ASSERT_EQ(t.size(), 4u);
      for (int v = 0; v < 4; ++v)
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(t[size_t(v)][k], c.want[k], 1e-6f) << "vertex " << v << " component " << k;
    }
  }
  // A tilted normal: the tangent is made orthogonal to it (Gram-Schmidt).
  const glm::vec3 tilted = glm::normalize(glm::vec3(1, 0, 1));
  const std::vector<glm::vec4> t = generate_tangents(p, std::vector<glm::vec3>(4, tilted), cases[0].uv, tris);
  for (const glm::vec4& v : t) {
    EXPECT_NEAR(glm::dot(glm::vec3(v), tilted), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec3(v)), 1.0f, 1e-6f);
  }
  const std::vector<glm::vec4> flat = generate_tangents(p, n, std::vector<glm::vec2>(4, glm::vec2(0.5f)), tris);
  for (const glm::vec4& v : flat) EXPECT_EQ(v, glm::vec4(0.0f));
}

}  // namespace
}  // namespace clpt::material_test
