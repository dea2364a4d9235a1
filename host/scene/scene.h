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

// A decoded image, RGBA, row 0 at the top (v = 0). Colour-space decoding (sRGB for colour
// textures) happens where a material reads it, since one image may serve both. 8 bits a
// channel, except a 16-bit image read only as a normal map (`wide`, the glTF loader decides).
struct Texture {
  enum class Wrap : uint8_t { Repeat, Clamp, Mirror };  // glTF sampler wrapS / wrapT
  std::string name;                                      // for messages: image name or URI
  uint32_t width = 0, height = 0;
  // width * height texels: one word each, R in the low byte; `wide`: two words each,
  // R | G << 16 then B | A << 16 (dev::TEXTURE_WIDE).
  std::vector<uint32_t> texels;
  bool wide = false;
  Wrap wrap_s = Wrap::Repeat, wrap_t = Wrap::Repeat;
  bool nearest = false;          // magFilter NEAREST; default bilinear

  // Texel i (row-major) as 8-bit RGBA, R in the low byte, whichever the format.
  uint32_t rgba8(size_t i) const;
};

// 16-bit RGBA words (two a texel, R | G << 16 then B | A << 16) to 8-bit (one a texel), each
// channel rounded to the nearest 8-bit value.
std::vector<uint32_t> narrow_texels(const std::vector<uint32_t>& wide);

// Where a material reads a texture: which one, which UV set, and KHR_texture_transform as a
// 2x3 matrix uv' = transform * (u, v, 1).
struct TextureRef {
  int texture = -1;  // index into Scene::textures; -1: none
  uint32_t texcoord = 0;
  glm::mat3x2 transform{1.0f};  // glm: 3 columns of 2 rows
  bool used() const { return texture >= 0; }
};

struct Material {
  enum class AlphaMode : uint8_t { Opaque, Mask, Blend };
  std::string name;
  glm::vec4 base_color{1.0f};  // linear RGBA (glTF baseColorFactor)
  glm::vec3 emission{0.0f};    // emitted radiance: emissiveFactor x KHR_materials_emissive_strength
  float metallic = 1.0f;       // glTF defaults
  float roughness = 1.0f;
  bool double_sided = false;
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  float normal_scale = 1.0f;
  float ior = 1.5f;             // KHR_materials_ior
  float transmission = 0.0f;    // KHR_materials_transmission
  float specular = 1.0f;        // KHR_materials_specular
  glm::vec3 specular_color{1.0f};
  glm::vec3 attenuation_color{1.0f};  // KHR_materials_volume
  float attenuation_distance = std::numeric_limits<float>::infinity();
  bool volume = false;          // KHR_materials_volume with a finite attenuation distance
  float clearcoat = 0.0f;       // KHR_materials_clearcoat
  float clearcoat_roughness = 0.0f;
  float clearcoat_normal_scale = 1.0f;  // clearcoatNormalTexture.scale
  float iridescence = 0.0f;     // KHR_materials_iridescence
  float iridescence_ior = 1.3f;
  float iridescence_thickness_min = 100.0f;  // nm
  float iridescence_thickness_max = 400.0f;
  float diffuse_transmission = 0.0f;  // KHR_materials_diffuse_transmission
  glm::vec3 diffuse_transmission_color{1.0f};
  glm::vec3 sheen_color{0.0f};        // KHR_materials_sheen: no sheen
  float sheen_roughness = 0.0f;
  float dispersion = 0.0f;            // KHR_materials_dispersion: 20 / Abbe number (0: none)
  float anisotropy_strength = 0.0f;   // KHR_materials_anisotropy: isotropic
  float anisotropy_rotation = 0.0f;   // radians, counter-clockwise from the tangent

  TextureRef base_color_texture, metallic_roughness_texture, normal_texture, emissive_texture,
      transmission_texture, specular_texture, specular_color_texture, clearcoat_texture,
      clearcoat_roughness_texture, iridescence_texture, iridescence_thickness_texture,
      diffuse_transmission_texture, diffuse_transmission_color_texture, sheen_color_texture,
      sheen_roughness_texture, anisotropy_texture, clearcoat_normal_texture;
};

// A KHR_lights_punctual light placed by its node, in world space.
struct PunctualLight {
  enum class Type : uint8_t { Point, Spot, Directional };
  std::string name;
  Type type = Type::Point;
  glm::vec3 color{1.0f};     // linear
  float intensity = 1.0f;    // candela (point, spot) or lux (directional), as glTF
  float range = 0.0f;        // 0: infinite (glTF's range is a culling hint; not used)
  glm::vec3 position{0.0f};  // point, spot
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // spot, directional: unit, the way light travels
  float inner_cone = 0.0f;   // spot, radians
  float outer_cone = 0.785398163f;
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
  // Optional attributes: empty when no primitive has them, else as long as positions.
  std::vector<glm::vec4> tangents;   // world space xyz unit, w = bitangent sign; zero: none
  std::vector<glm::vec2> uvs1;       // TEXCOORD_1
  std::vector<glm::vec4> colors;     // COLOR_0, linear RGBA; 1 where a primitive has none

  // Triangles index the vertex arrays; counter-clockwise winding is the front face.
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> triangle_materials;  // one per triangle, indexes materials

  std::vector<Material> materials;  // never empty once loaded (a default is added)
  std::vector<Camera> cameras;      // from the file, in node traversal order of the scene
  std::vector<Texture> textures;
  std::vector<PunctualLight> lights; // KHR_lights_punctual, in node traversal order

  Bounds bounds() const;
  size_t emissive_triangle_count() const;
};

// A perspective camera (45 degree vertical field of view) on the +Z side of the bounds,
// looking down -Z at their centre, far enough that the bounding sphere fits the view.
Camera default_camera(const Bounds& bounds);

}  // namespace clpt
