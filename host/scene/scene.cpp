#include "scene/scene.h"

#include <cmath>

namespace clpt {

namespace {

// A 16-bit channel to the nearest 8-bit value: round(v * 255 / 65535) = round(v / 257).
uint32_t to8(uint32_t v) { return (v + 128u) / 257u; }

uint32_t narrow(uint32_t rg, uint32_t ba) {
  return to8(rg & 65535u) | to8(rg >> 16) << 8 | to8(ba & 65535u) << 16 | to8(ba >> 16) << 24;
}

}  // namespace

uint32_t Texture::rgba8(size_t i) const { return wide ? narrow(texels[2 * i], texels[2 * i + 1]) : texels[i]; }

std::vector<uint32_t> narrow_texels(const std::vector<uint32_t>& wide) {
  std::vector<uint32_t> out(wide.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) out[i] = narrow(wide[2 * i], wide[2 * i + 1]);
  return out;
}

Bounds Scene::bounds() const {
  Bounds b;
  for (const glm::vec3& p : positions) b.extend(p);
  return b;
}

size_t Scene::emissive_triangle_count() const {
  size_t count = 0;
  for (size_t i = 0; i < triangles.size() && i < triangle_materials.size(); ++i) {
    const uint32_t m = triangle_materials[i];
    if (m >= materials.size()) continue;
    const glm::vec3& e = materials[m].emission;
    if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) ++count;
  }
  return count;
}

Camera default_camera(const Bounds& bounds) {
  Camera cam;
  cam.name = "default";
  cam.type = Camera::Type::Perspective;
  cam.yfov = 0.785398163f;  // 45 degrees
  cam.aspect = 0.0f;
  cam.camera_to_world = glm::mat4(1.0f);  // looks down -Z, +Y up

  const glm::vec3 center = bounds.center();
  const float radius = 0.5f * glm::length(bounds.extent());
  if (bounds.empty() || !std::isfinite(center.x) || !std::isfinite(center.y) || !std::isfinite(center.z) ||
      !std::isfinite(radius)) {
    cam.camera_to_world[3] = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);  // at (0,0,1) looking at the origin
    return cam;
  }
  // The bounding sphere touches the vertical field of view at distance r / sin(yfov / 2);
  // step back a little further so it does not touch the image border.
  const float margin = 1.1f;
  float distance = margin * radius / std::sin(0.5f * cam.yfov);
  if (!(distance > 0.0f)) distance = 1.0f;  // a single point
  cam.camera_to_world[3] = glm::vec4(center + glm::vec3(0.0f, 0.0f, distance), 1.0f);
  return cam;
}

}  // namespace clpt
