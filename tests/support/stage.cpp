#include "support/stage.h"

#include <cmath>
#include <stdexcept>

#include "support/mesh.h"
#include "support/render.h"
#include "support/scenes.h"

namespace clpt::test {
namespace {

constexpr float kPiF = 3.14159265358979f;
const glm::vec3 kCameraOrigin(0.5f, 0.32f, 1.0f);
constexpr float kYfov = 0.55f;
const glm::vec3 kSphereCentre(0.5f, 0.2f, -0.5f);
constexpr float kSphereRadius = 0.2f;
// GlassSheet: the sheet at z = kSheetZ, x and y within these bounds; the sphere behind it.
constexpr float kSheetZ = -0.2f;
constexpr float kSheetX0 = 0.28f, kSheetX1 = 0.72f, kSheetY1 = 0.45f;

Material diffuse(glm::vec3 albedo) {
  Material m;
  m.base_color = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;  // exactly Lambertian
  return m;
}

Material emitter(float radiance, bool double_sided) {
  Material m = diffuse(glm::vec3(0.0f));
  m.emission = glm::vec3(radiance);
  m.double_sided = double_sided;
  return m;
}

uint32_t rgba(uint32_t r, uint32_t g, uint32_t b, uint32_t a) {
  return r | g << 8 | b << 16 | a << 24;
}

int add_texture(Scene& scene, uint32_t w, uint32_t h, std::vector<uint32_t> texels, bool nearest) {
  Texture t;
  t.width = w;
  t.height = h;
  t.texels = std::move(texels);
  t.nearest = nearest;
  scene.textures.push_back(std::move(t));
  return int(scene.textures.size()) - 1;
}

// Adds the quad p0 p1 p2 p3 (counter-clockwise seen from its front) with flat shading.
void add_quad(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3,
              const Material& m) {
  Mesh q;
  q.positions = {p0, p1, p2, p3};
  q.triangles = {{0, 1, 2}, {0, 2, 3}};
  add_mesh(scene, q, m);
}

// An axis-aligned quad in the plane `axis` = c, spanning [lo, hi] in the other two axes,
// facing +axis (sign > 0) or -axis.
void add_axis_quad(Scene& scene, int axis, float c, glm::vec2 lo, glm::vec2 hi, float sign,
                   const Material& m) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  auto corner = [&](float u, float v) {
    glm::vec3 p(0.0f);
    p[axis] = c;
    p[a] = u;
    p[b] = v;
    return p;
  };
  // (a, b, axis) is right-handed, so lo-lo, hi-lo, hi-hi, lo-hi is counter-clockwise seen
  // from +axis.
  const glm::vec3 q0 = corner(lo.x, lo.y), q1 = corner(hi.x, lo.y), q2 = corner(hi.x, hi.y),
                  q3 = corner(lo.x, hi.y);
  if (sign > 0.0f) add_quad(scene, q0, q1, q2, q3, m);
  else add_quad(scene, q0, q3, q2, q1, m);
}

// A latitude-longitude sphere with smooth normals, u around +y, v from the top (0) to the
// bottom (1), tangents along increasing u; seam vertices repeated so the UVs do not wrap.
void add_uv_sphere(Scene& scene, glm::vec3 c, float r, const Material& m, int segments = 32,
                   int rings = 16) {
  const uint32_t base = uint32_t(scene.positions.size());
  const uint32_t mat = uint32_t(scene.materials.size());
  scene.materials.push_back(m);
  const bool tangents = !scene.tangents.empty() || m.normal_texture.used() || m.anisotropy_strength > 0.0f;
  if (tangents && scene.tangents.empty()) scene.tangents.assign(scene.positions.size(), glm::vec4(0.0f));
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPiF * float(i) / float(rings);
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2.0f * kPiF * float(j) / float(segments);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                        -std::sin(theta) * std::sin(phi));
      scene.positions.push_back(c + r * n);
      scene.normals.push_back(n);
      scene.uvs.push_back(glm::vec2(float(j) / float(segments), float(i) / float(rings)));
      if (tangents) {
        // d/dphi of the position, unit; cross(n, t) points up the sphere, towards decreasing
        // v, so w = +1 (the glTF convention of host/scene/tangents.h).
        const glm::vec3 t(-std::sin(phi), 0.0f, -std::cos(phi));
        scene.tangents.push_back(glm::vec4(t, 1.0f));
      }
    }
  }
  const uint32_t row = uint32_t(segments + 1);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = base + uint32_t(i) * row + uint32_t(j), b = a + row;
      // Outward: (a, b, b+1) is counter-clockwise seen from outside.
      if (i != 0) {
        scene.triangles.push_back({a, b, a + 1});
        scene.triangle_materials.push_back(mat);
      }
      if (i != rings - 1) {
        scene.triangles.push_back({a + 1, b, b + 1});
        scene.triangle_materials.push_back(mat);
      }
    }
  if (!scene.tangents.empty()) scene.tangents.resize(scene.positions.size(), glm::vec4(0.0f));
}

Material object_material(Scene& scene, StageMaterial kind) {
  Material m = diffuse(glm::vec3(0.8f, 0.8f, 0.8f));
  switch (kind) {
    case StageMaterial::Lambert:
      break;
    case StageMaterial::Metal005:
    case StageMaterial::Metal03:
    case StageMaterial::Metal1: {
      const float alpha = kind == StageMaterial::Metal005 ? 0.05f : kind == StageMaterial::Metal03 ? 0.3f : 1.0f;
      m.base_color = glm::vec4(0.9f, 0.7f, 0.5f, 1.0f);
      m.metallic = 1.0f;
      m.roughness = std::sqrt(alpha);
      m.specular = 1.0f;
      break;
    }
    case StageMaterial::GlassSmooth:
    case StageMaterial::GlassRough:
    case StageMaterial::GlassAbsorbing:
    case StageMaterial::GlassSheet:
    case StageMaterial::DispersiveGlass:
      m = glass_material(kind == StageMaterial::GlassSmooth ? 0.0f : 0.3f);
      // Abbe number 10 (a dense flint glass has about 30): indices 1.494 (red), 1.511 (green)
      // and 1.546 (blue), so that the channels' light through the sphere lands apart.
      if (kind == StageMaterial::DispersiveGlass) m.dispersion = 2.0f;
      if (kind == StageMaterial::GlassAbsorbing) {
        m.volume = true;
        m.attenuation_color = glm::vec3(0.9f, 0.4f, 0.2f);
        m.attenuation_distance = 0.3f;
      }
      break;
    case StageMaterial::Specular:
      m.base_color = glm::vec4(0.3f, 0.5f, 0.8f, 1.0f);
      m.roughness = 0.4f;
      m.specular = 0.5f;
      m.specular_color = glm::vec3(1.0f, 0.6f, 0.3f);
      break;
    case StageMaterial::NormalMap: {
      // Stripes along u whose normals lean +-0.5 towards the tangent.
      std::vector<uint32_t> texels;
      for (int i = 0; i < 16; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(i % 2 ? 0.5f : -0.5f, 0.0f, 1.0f));
        const auto enc = [](float x) { return uint32_t(std::lround((0.5f * x + 0.5f) * 255.0f)); };
        texels.push_back(rgba(enc(n.x), enc(n.y), enc(n.z), 255));
      }
      m.normal_texture.texture = add_texture(scene, 16, 1, texels, true);
      m.roughness = 0.5f;
      m.specular = 1.0f;
      break;
    }
    case StageMaterial::AlphaMask: {
      std::vector<uint32_t> texels;
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) texels.push_back(rgba(255, 255, 255, (x + y) % 2 ? 255 : 0));
      m.base_color_texture.texture = add_texture(scene, 8, 8, texels, true);
      m.alpha_mode = Material::AlphaMode::Mask;
      m.double_sided = true;
      break;
    }
    case StageMaterial::AlphaBlend:
      m.base_color.w = 0.5f;
      m.alpha_mode = Material::AlphaMode::Blend;
      m.double_sided = true;
      break;
    case StageMaterial::EmissiveTexture: {
      std::vector<uint32_t> texels;
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) texels.push_back((x + y) % 2 ? rgba(255, 200, 120, 255) : rgba(0, 0, 0, 255));
      m.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
      m.emission = glm::vec3(1.5f);
      m.emissive_texture.texture = add_texture(scene, 8, 4, texels, true);
      break;
    }
    case StageMaterial::Clearcoat:
      // A rough red plastic under a glossy KHR_materials_clearcoat (alpha 0.0225).
      m.base_color = glm::vec4(0.7f, 0.15f, 0.1f, 1.0f);
      m.roughness = 0.6f;
      m.specular = 1.0f;
      m.clearcoat = 1.0f;
      m.clearcoat_roughness = 0.15f;
      break;
    case StageMaterial::IridescentGlass:
      // The film colours reflection and, through 1 - r, transmission; seen from inside it
      // must reflect as from outside (kernels/bsdf/gltf_bsdf.cl, gltf_glass_r).
      m = glass_material(0.3f);
      m.iridescence = 1.0f;
      m.iridescence_ior = 1.8f;
      m.iridescence_thickness_max = 450.0f;
      break;
    case StageMaterial::Translucent:
      // Light enters the closed object diffusely, scatters off its inside and leaves it.
      m.base_color = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
      m.roughness = 0.5f;
      m.specular = 1.0f;
      m.diffuse_transmission = 0.6f;
      m.diffuse_transmission_color = glm::vec3(0.9f, 0.5f, 0.3f);
      m.double_sided = true;
      break;
    case StageMaterial::Sheen:
      // Velvet: the sheen's grazing glow over a dark base. At roughness 0.25 the lobe's cap
      // (kernels/bsdf/sheen.cl) is active at grazing angles, so its symmetry is tested too.
      m.base_color = glm::vec4(0.35f, 0.05f, 0.05f, 1.0f);
      m.roughness = 0.8f;
      m.specular = 1.0f;
      m.sheen_color = glm::vec3(1.0f, 0.7f, 0.6f);
      m.sheen_roughness = 0.25f;
      break;
    case StageMaterial::Anisotropic:
      // Brushed metal: alpha 0.09 across the brushing, mix(0.09, 1, 0.64) = 0.67 along it,
      // turned 0.5 rad from the sphere's tangent (along u) towards its bitangent.
      m.base_color = glm::vec4(0.9f, 0.75f, 0.55f, 1.0f);
      m.metallic = 1.0f;
      m.roughness = 0.3f;
      m.anisotropy_strength = 0.8f;
      m.anisotropy_rotation = 0.5f;
      break;
  }
  return m;
}

bool open_stage(StageLight l) { return l == StageLight::Directional || l == StageLight::Environment; }

void add_stage(Scene& scene, StageLight light) {
  const Material grey = diffuse(glm::vec3(0.7f)), red = diffuse(glm::vec3(0.7f, 0.25f, 0.2f)),
                 green = diffuse(glm::vec3(0.25f, 0.7f, 0.3f));
  if (open_stage(light)) {
    add_axis_quad(scene, 1, 0.0f, {-1.5f, -0.5f}, {1.0f, 2.5f}, 1.0f, grey);  // floor (z, x)
    add_axis_quad(scene, 2, -1.0f, {-0.5f, 0.0f}, {2.5f, 1.5f}, 1.0f, grey);  // back wall (x, y)
    return;
  }
  add_axis_quad(scene, 1, 0.0f, {-1.0f, 0.0f}, {0.0f, 1.0f}, 1.0f, grey);    // floor
  add_axis_quad(scene, 1, 1.0f, {-1.0f, 0.0f}, {0.0f, 1.0f}, -1.0f, grey);   // ceiling
  add_axis_quad(scene, 2, -1.0f, {0.0f, 0.0f}, {1.0f, 1.0f}, 1.0f, grey);    // back wall
  add_axis_quad(scene, 0, 0.0f, {0.0f, -1.0f}, {1.0f, 0.0f}, 1.0f, red);     // left wall (y, z)
  add_axis_quad(scene, 0, 1.0f, {0.0f, -1.0f}, {1.0f, 0.0f}, -1.0f, green);  // right wall
}

void add_light(Scene& scene, StageLight light) {
  switch (light) {
    case StageLight::AreaDown:
      add_axis_quad(scene, 1, 0.98f, {-0.65f, 0.35f}, {-0.35f, 0.65f}, -1.0f, emitter(12.0f, false));
      break;
    case StageLight::AreaUp: {
      // 10 cm under the ceiling: shadow rays to the ceiling are short (issue 14's NEE bug).
      add_axis_quad(scene, 1, 0.9f, {-0.56f, 0.44f}, {-0.44f, 0.56f}, 1.0f, emitter(60.0f, false));
      Mesh shade;  // a closed diffuse box 1 cm under the panel
      const glm::vec3 lo(0.42f, 0.87f, -0.58f), hi(0.58f, 0.89f, -0.42f);
      const Mesh cube = grid_cube(0.5f * (lo + hi), 1.0f, 1);
      for (glm::vec3 p : cube.positions) {
        const glm::vec3 half = 0.5f * (hi - lo);
        shade.positions.push_back(0.5f * (lo + hi) + (p - 0.5f * (lo + hi)) * half);
      }
      shade.triangles = cube.triangles;
      add_mesh(scene, shade, diffuse(glm::vec3(0.8f)));
      break;
    }
    case StageLight::AreaSide:
      add_axis_quad(scene, 0, 0.01f, {0.45f, -0.62f}, {0.7f, -0.37f}, 1.0f, emitter(15.0f, false));
      break;
    case StageLight::AreaDouble:
      add_axis_quad(scene, 0, 0.82f, {0.3f, -0.6f}, {0.5f, -0.4f}, 1.0f, emitter(10.0f, true));
      break;
    case StageLight::Point: {
      PunctualLight l;
      l.type = PunctualLight::Type::Point;
      l.position = glm::vec3(0.5f, 0.85f, -0.45f);
      l.intensity = 0.6f;
      scene.lights.push_back(l);
      break;
    }
    case StageLight::Spot: {
      PunctualLight l;
      l.type = PunctualLight::Type::Spot;
      l.position = glm::vec3(0.2f, 0.8f, -0.2f);
      l.direction = glm::normalize(kSphereCentre - l.position);
      l.intensity = 1.5f;
      l.inner_cone = 25.0f * kPiF / 180.0f;
      l.outer_cone = 35.0f * kPiF / 180.0f;
      scene.lights.push_back(l);
      break;
    }
    case StageLight::Directional: {
      PunctualLight l;
      l.type = PunctualLight::Type::Directional;
      l.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
      l.intensity = 3.0f;
      scene.lights.push_back(l);
      break;
    }
    case StageLight::Environment:
      break;  // stage_settings' background
  }
}

}  // namespace

std::string stage_material_name(StageMaterial m) {
  switch (m) {
    case StageMaterial::Lambert: return "lambert";
    case StageMaterial::Metal005: return "metal_a005";
    case StageMaterial::Metal03: return "metal_a03";
    case StageMaterial::Metal1: return "metal_a1";
    case StageMaterial::GlassSmooth: return "glass_smooth";
    case StageMaterial::GlassRough: return "glass_rough";
    case StageMaterial::GlassAbsorbing: return "glass_absorbing";
    case StageMaterial::GlassSheet: return "glass_sheet";
    case StageMaterial::Specular: return "specular";
    case StageMaterial::NormalMap: return "normal_map";
    case StageMaterial::AlphaMask: return "alpha_mask";
    case StageMaterial::AlphaBlend: return "alpha_blend";
    case StageMaterial::EmissiveTexture: return "emissive_texture";
    case StageMaterial::Clearcoat: return "clearcoat";
    case StageMaterial::IridescentGlass: return "iridescent_glass";
    case StageMaterial::Translucent: return "translucent";
    case StageMaterial::Sheen: return "sheen";
    case StageMaterial::Anisotropic: return "anisotropic";
    case StageMaterial::DispersiveGlass: return "glass_dispersive";
  }
  throw std::logic_error("stage material");
}

std::string stage_light_name(StageLight l) {
  switch (l) {
    case StageLight::AreaDown: return "area_down";
    case StageLight::AreaUp: return "area_up";
    case StageLight::AreaSide: return "area_side";
    case StageLight::AreaDouble: return "area_double";
    case StageLight::Point: return "point";
    case StageLight::Spot: return "spot";
    case StageLight::Directional: return "directional";
    case StageLight::Environment: return "environment";
  }
  throw std::logic_error("stage light");
}

bool stage_light_is_delta(StageLight l) {
  return l == StageLight::Point || l == StageLight::Spot || l == StageLight::Directional;
}

Scene stage_scene(StageMaterial material, StageLight light) {
  Scene scene;
  add_stage(scene, light);
  add_light(scene, light);
  const Material m = object_material(scene, material);
  if (material == StageMaterial::GlassSheet) {
    add_uv_sphere(scene, kSphereCentre, kSphereRadius, diffuse(glm::vec3(0.8f)));
    add_axis_quad(scene, 2, kSheetZ, {kSheetX0, 0.0f}, {kSheetX1, kSheetY1}, 1.0f, m);
  } else {
    add_uv_sphere(scene, kSphereCentre, kSphereRadius, m);
  }
  Camera cam;
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(kCameraOrigin, 1.0f);
  cam.yfov = kYfov;
  cam.aspect = 1.0f;
  scene.cameras.push_back(cam);
  return scene;
}

RenderSettings stage_settings(StageLight light, const std::string& integrator, uint64_t spp,
                              uint32_t size) {
  RenderSettings s = render_settings(integrator, spp, size);
  if (light == StageLight::Environment) s.background = glm::vec3(0.8f, 0.85f, 1.0f);
  return s;
}

std::vector<uint8_t> stage_regions(StageMaterial material, uint32_t size) {
  std::vector<uint8_t> region(size_t(size) * size, REGION_REST);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const glm::vec3 d = pixel_centre_direction(x, y, size, kYfov);  // the camera is unrotated
      const glm::vec3 o = kCameraOrigin;
      uint8_t& r = region[size_t(y) * size + x];
      if (material == StageMaterial::GlassSheet) {
        const float t = (kSheetZ - o.z) / d.z;
        const glm::vec3 p = o + t * d;
        if (p.x > kSheetX0 && p.x < kSheetX1 && p.y > 0.0f && p.y < kSheetY1) {
          r = REGION_OBJECT;
          continue;
        }
      } else if (ray_sphere(o, d, kSphereCentre, kSphereRadius) > 0.0f) {
        r = REGION_OBJECT;
        continue;
      }
      if (d.y < 0.0f) {
        const glm::vec3 p = o + (-o.y / d.y) * d;
        const float dx = p.x - kSphereCentre.x, dz = p.z - kSphereCentre.z;
        if (p.z > -1.0f && dx * dx + dz * dz < 0.45f * 0.45f) r = REGION_NEAR;
      }
    }
  return region;
}

const char* stage_region_name(int region) {
  return region == REGION_OBJECT ? "object" : region == REGION_NEAR ? "near" : "rest";
}

}  // namespace clpt::test
