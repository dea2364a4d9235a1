// The renderer's own scene description: world-space triangles with per-vertex attributes,
// materials and cameras. Format-neutral: only scene/gltf_loader knows glTF.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace clpt {

struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Bounds& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  glm::vec3 center() const { return 0.5f * (min + max); }
  glm::vec3 extent() const { return max - min; }
};

struct Material {
  std::string name;
  glm::vec4 base_color{1.0f};  // linear RGBA (glTF baseColorFactor)
  glm::vec3 emission{0.0f};    // emitted radiance: emissiveFactor x KHR_materials_emissive_strength
  float metallic = 1.0f;       // glTF defaults
  float roughness = 1.0f;
  bool double_sided = false;
};

struct Camera {
  enum class Type { Perspective, Orthographic };
  std::string name;
  Type type = Type::Perspective;
  // Camera space as glTF: looks down -Z, +Y up, +X right. Rigid (scale removed).
  glm::mat4 camera_to_world{1.0f};
  float yfov = 0.785398163f;  // radians, perspective only
  float aspect = 0.0f;        // width / height; 0 when the file does not give one
  float xmag = 1.0f;          // orthographic half extents
  float ymag = 1.0f;
};

struct Scene {
  // Vertex attributes, all the same length. A zero normal means "no shading normal":
  // the kernel then shades with the geometric normal.
  std::vector<glm::vec3> positions;  // world space
  std::vector<glm::vec3> normals;    // world space, unit or zero
  std::vector<glm::vec2> uvs;        // first UV set (TEXCOORD_0), zero when absent

  // Triangles index the vertex arrays; counter-clockwise winding is the front face.
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> triangle_materials;  // one per triangle, indexes materials

  std::vector<Material> materials;  // never empty once loaded (a default is added)
  std::vector<Camera> cameras;      // from the file, in node traversal order of the scene

  Bounds bounds() const;
  size_t emissive_triangle_count() const;
};

// A perspective camera (45 degree vertical field of view) on the +Z side of the bounds,
// looking down -Z at their centre, far enough that the bounding sphere fits the view.
Camera default_camera(const Bounds& bounds);

}  // namespace clpt
