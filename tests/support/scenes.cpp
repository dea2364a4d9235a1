#include "support/scenes.h"

#include <cmath>

#include "scene/gltf_loader.h"

namespace clpt::test {

void add_mesh(Scene& scene, const Mesh& mesh, const Material& material) {
  const uint32_t base = static_cast<uint32_t>(scene.positions.size());
  const uint32_t mat = static_cast<uint32_t>(scene.materials.size());
  scene.materials.push_back(material);
  for (const glm::vec3& p : mesh.positions) {
    scene.positions.push_back(p);
    scene.normals.push_back(glm::vec3(0.0f));
    scene.uvs.push_back(glm::vec2(0.0f));
  }
  for (const glm::uvec3& t : mesh.triangles) {
    scene.triangles.push_back(t + glm::uvec3(base));
    scene.triangle_materials.push_back(mat);
  }
}

void add_camera_on_z(Scene& scene, float z, float yfov) {
  Camera cam;
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(0.0f, 0.0f, z, 1.0f);
  cam.yfov = yfov;
  cam.aspect = 1.0f;
  scene.cameras.push_back(cam);
}

Scene furnace_scene(float rho, float Le) {
  Scene scene;
  Material m;
  m.base_color = glm::vec4(rho, rho, rho, 1.0f);
  m.emission = glm::vec3(Le);
  m.metallic = 0.0f;
  m.specular = 0.0f;  // KHR_materials_specular 0: exactly Lambertian, as the closed form needs
  m.double_sided = true;
  add_mesh(scene, icosphere(glm::vec3(0.0f), 1.0f, 3), m);
  Mesh outer = icosphere(glm::vec3(0.0f), 5.0f, 3);
  for (glm::uvec3& t : outer.triangles) std::swap(t.y, t.z);  // face inwards
  add_mesh(scene, outer, m);
  add_camera_on_z(scene, 3.5f, 0.785398163f);
  return scene;
}

double furnace_radiance(double rho, double Le, unsigned max_depth) {
  return Le * (1.0 - std::pow(rho, double(max_depth) + 1.0)) / (1.0 - rho);
}

void PrintTo(const FurnaceCase& c, std::ostream* os) {
  *os << "rho " << c.rho << ", max depth " << c.max_depth;
}

std::string furnace_case_name(const FurnaceCase& c) {
  return "rho" + std::to_string(int(c.rho * 100)) + "_depth" + std::to_string(c.max_depth);
}

glm::vec3 pixel_centre_direction(uint32_t x, uint32_t y, uint32_t size, float yfov) {
  const float tan_half = std::tan(0.5f * yfov);
  const float fx = 2.0f * (float(x) + 0.5f) / float(size) - 1.0f;
  const float fy = 1.0f - 2.0f * (float(y) + 0.5f) / float(size);
  return glm::normalize(glm::vec3(fx * tan_half, fy * tan_half, -1.0f));
}

float ray_sphere(glm::vec3 o, glm::vec3 d, glm::vec3 c, float r) {
  const glm::vec3 oc = o - c;
  const float b = glm::dot(oc, d), cc = glm::dot(oc, oc) - r * r, disc = b * b - cc;
  if (disc < 0.0f) return -1.0f;
  const float t = -b - std::sqrt(disc);
  return t > 0.0f ? t : -1.0f;
}

Material glass_material(float roughness, float ior) {
  Material m;
  m.base_color = glm::vec4(1.0f);
  m.metallic = 0.0f;
  m.roughness = roughness;
  m.specular = 1.0f;
  m.transmission = 1.0f;
  m.ior = ior;
  return m;
}

Scene cornell_box() { return load_gltf(std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf"); }

Scene cornell_box_glossy_glass() {
  Scene scene = cornell_box();
  Material metal = scene.materials[0];
  metal.name = "glossy_metal";
  metal.base_color = glm::vec4(0.9f, 0.8f, 0.6f, 1.0f);
  metal.metallic = 1.0f;
  metal.roughness = 0.3f;
  metal.specular = 1.0f;
  Material glass = scene.materials[0];
  glass.name = "glass";
  glass.base_color = glm::vec4(1.0f);
  glass.metallic = 0.0f;
  glass.roughness = 0.0f;
  glass.specular = 1.0f;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  const auto metal_index = static_cast<uint32_t>(scene.materials.size());
  scene.materials.push_back(metal);
  scene.materials.push_back(glass);
  // The blocks' triangles, by their centroids (scenes/cornell_box.gltf: the short block
  // spans x 0.266..0.474, z -0.272..-0.065; the tall one x 0.084..0.291, z -0.456..-0.247).
  auto inside = [](glm::vec3 c, glm::vec3 lo, glm::vec3 hi) {
    return glm::all(glm::greaterThan(c, lo - 1e-3f)) && glm::all(glm::lessThan(c, hi + 1e-3f));
  };
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const glm::vec3 c = (scene.positions[t.x] + scene.positions[t.y] + scene.positions[t.z]) / 3.0f;
    if (c.y <= 1e-4f) continue;  // the floor
    if (inside(c, {0.266f, 0.0f, -0.272f}, {0.474f, 0.165f, -0.065f}))
      scene.triangle_materials[i] = metal_index + 1;
    else if (inside(c, {0.084f, 0.0f, -0.456f}, {0.291f, 0.33f, -0.247f}))
      scene.triangle_materials[i] = metal_index;
  }
  return scene;
}

Scene cornell_box_all_lights() {
  Scene scene = cornell_box();
  PunctualLight sun;
  sun.type = PunctualLight::Type::Directional;
  sun.intensity = 2.0f;
  sun.direction = glm::normalize(glm::vec3(0.3f, -0.5f, -1.0f));
  scene.lights.push_back(sun);
  PunctualLight point;
  point.type = PunctualLight::Type::Point;
  point.intensity = 0.02f;
  point.color = glm::vec3(0.5f, 0.7f, 1.0f);
  point.position = glm::vec3(0.15f, 0.45f, -0.15f);
  scene.lights.push_back(point);
  PunctualLight spot;
  spot.type = PunctualLight::Type::Spot;
  spot.intensity = 0.05f;
  spot.position = glm::vec3(0.45f, 0.5f, -0.45f);
  spot.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, 0.4f));
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.5f;
  scene.lights.push_back(spot);
  return scene;
}

}  // namespace clpt::test
