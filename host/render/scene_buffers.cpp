// The scene flattened into the arrays of kernels/shared/scene_types.h (FlatScene), and their
// device buffers. The lights in them are built by render/light_table.cpp.
#include "render/scene_buffers.h"

#include "render/mipmaps.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clpt {
namespace {

dev::TextureSlot to_device(const TextureRef& r) {
  dev::TextureSlot d{};
  d.texture = r.texture;
  d.texcoord = r.texcoord;
  // glm::mat3x2: column c holds the coefficients of u (0), v (1) and 1 (2).
  d.m[0] = r.transform[0][0];
  d.m[1] = r.transform[1][0];
  d.m[2] = r.transform[2][0];
  d.m[3] = r.transform[0][1];
  d.m[4] = r.transform[1][1];
  d.m[5] = r.transform[2][1];
  return d;
}

dev::Material to_device(const Material& m) {
  dev::Material d{};
  for (int i = 0; i < 4; ++i) d.base_color[i] = m.base_color[i];
  for (int i = 0; i < 3; ++i) d.emission[i] = m.emission[i];
  d.metallic = m.metallic;
  d.roughness = m.roughness;
  d.alpha_cutoff = m.alpha_cutoff;
  d.ior = m.ior;
  d.transmission = m.transmission;
  d.specular = m.specular;
  d.normal_scale = m.normal_scale;
  d.attenuation_distance = m.attenuation_distance;
  d.clearcoat = m.clearcoat;
  d.clearcoat_roughness = m.clearcoat_roughness;
  d.clearcoat_normal_scale = m.clearcoat_normal_scale;
  d.dispersion = m.dispersion;
  d.iridescence = m.iridescence;
  d.iridescence_ior = m.iridescence_ior;
  d.iridescence_thickness_min = m.iridescence_thickness_min;
  d.iridescence_thickness_max = m.iridescence_thickness_max;
  d.diffuse_transmission = m.diffuse_transmission;
  for (int i = 0; i < 3; ++i) d.diffuse_transmission_color[i] = m.diffuse_transmission_color[i];
  d.sheen_roughness = m.sheen_roughness;
  for (int i = 0; i < 3; ++i) d.sheen_color[i] = m.sheen_color[i];
  d.anisotropy[0] = m.anisotropy_strength;
  d.anisotropy[1] = std::cos(m.anisotropy_rotation);
  d.anisotropy[2] = std::sin(m.anisotropy_rotation);
  for (int i = 0; i < 3; ++i) d.specular_color[i] = m.specular_color[i];
  for (int i = 0; i < 3; ++i) d.attenuation_color[i] = m.attenuation_color[i];
  d.flags = 0u;
  if (m.double_sided) d.flags |= dev::MATERIAL_DOUBLE_SIDED;
  if (m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f)
    d.flags |= dev::MATERIAL_EMISSIVE;
  if (m.alpha_mode == Material::AlphaMode::Mask) d.flags |= dev::MATERIAL_ALPHA_MASK;
  if (m.alpha_mode == Material::AlphaMode::Blend) d.flags |= dev::MATERIAL_ALPHA_BLEND;
  if (m.volume) d.flags |= dev::MATERIAL_VOLUME;
  if (m.anisotropy_strength > 0.0f) d.flags |= dev::MATERIAL_ANISOTROPIC;
  const TextureRef* refs[dev::TEX_SLOT_COUNT] = {
      &m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
      &m.emissive_texture,   &m.transmission_texture,       &m.specular_texture,
      &m.specular_color_texture, &m.clearcoat_texture,        &m.clearcoat_roughness_texture,
      &m.iridescence_texture,    &m.iridescence_thickness_texture,
      &m.diffuse_transmission_texture, &m.diffuse_transmission_color_texture,
      &m.sheen_color_texture,    &m.sheen_roughness_texture,   &m.anisotropy_texture,
      &m.clearcoat_normal_texture};
  bool any_texture = false;
  for (int i = 0; i < dev::TEX_SLOT_COUNT; ++i) {
    d.tex[i] = to_device(*refs[i]);
    any_texture = any_texture || d.tex[i].texture >= 0;
    if (refs[i]->used() && i != dev::TEX_EMISSIVE) d.flags |= dev::MATERIAL_TEXTURED;
  }
  // The kernels' tests for each layer, as they are written there (material_resolve_full), on
  // the device struct's own values (fmax, as the kernels' max_component).
  const bool layered = d.clearcoat > 0.0f || d.iridescence > 0.0f ||
                       d.diffuse_transmission > 0.0f ||
                       std::fmax(d.sheen_color[0], std::fmax(d.sheen_color[1], d.sheen_color[2])) > 0.0f ||
                       (d.flags & dev::MATERIAL_ANISOTROPIC) != 0u;
  if (!any_texture && !layered) d.flags |= dev::MATERIAL_PLAIN;
  return d;
}

}  // namespace

int bvh_max_leaf(const cl::DeviceInfo& device) {
  return cl::triangle_lanes(device) ? kMaxLeafLanes : kMaxLeafOneAtATime;
}

FlatScene flatten_scene(const Scene& scene, const Bvh& bvh, const Environment& env, bool mipmaps) {
  FlatScene flat;
  flat.nodes = bvh.wide;
  flat.bvh_depth = bvh.depth;
  flat.triangles.resize(bvh.triangle_order.size());
  for (size_t i = 0; i < bvh.triangle_order.size(); ++i) {
    const uint32_t src = bvh.triangle_order[i];
    const glm::uvec3& t = scene.triangles[src];
    flat.triangles[i] = dev::Triangle{{t.x, t.y, t.z}, scene.triangle_materials[src]};
  }
  const size_t nv = scene.positions.size();
  flat.vertices.resize(nv);
  for (size_t i = 0; i < nv; ++i) {
    dev::Vertex& v = flat.vertices[i];
    const glm::vec3 p = scene.positions[i];
    const glm::vec3 n = i < scene.normals.size() ? scene.normals[i] : glm::vec3(0.0f);
    const glm::vec2 uv = i < scene.uvs.size() ? scene.uvs[i] : glm::vec2(0.0f);
    v = dev::Vertex{{p.x, p.y, p.z}, uv.x, {n.x, n.y, n.z}, uv.y};
  }
  if (!scene.tangents.empty() || !scene.uvs1.empty() || !scene.colors.empty()) {
    flat.info.flags |= dev::SCENE_VERTEX_EXTRA;
    flat.vertex_extra.resize(nv);
    for (size_t i = 0; i < nv; ++i) {
      dev::VertexExtra& e = flat.vertex_extra[i];
      const glm::vec4 t = i < scene.tangents.size() ? scene.tangents[i] : glm::vec4(0.0f);
      const glm::vec4 c = i < scene.colors.size() ? scene.colors[i] : glm::vec4(1.0f);
      const glm::vec2 uv1 = i < scene.uvs1.size() ? scene.uvs1[i] : glm::vec2(0.0f);
      e = dev::VertexExtra{{t.x, t.y, t.z, t.w}, {c.x, c.y, c.z, c.w}, {uv1.x, uv1.y}, {0.0f, 0.0f}};
    }
  }
  flat.materials.reserve(scene.materials.size());
  for (const Material& m : scene.materials) {
    flat.materials.push_back(to_device(m));
    if (m.alpha_mode != Material::AlphaMode::Opaque) flat.info.flags |= dev::SCENE_ALPHA;
  }
  const std::vector<bool> srgb = textures_read_as_srgb(scene);
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& t = scene.textures[i];
    dev::Texture d{};
    d.offset = static_cast<dev::u32>(flat.texels.size());
    d.width = t.width;
    d.height = t.height;
    uint32_t levels = 1;
    std::vector<uint32_t> mips;
    if (mipmaps) mips = build_mip_levels(t.texels, t.width, t.height, srgb[i], &levels, t.wide);
    d.flags = static_cast<dev::u32>(t.wrap_s) |
              (static_cast<dev::u32>(t.wrap_t) << dev::TEXTURE_WRAP_T_SHIFT) |
              (t.nearest ? static_cast<dev::u32>(dev::TEXTURE_NEAREST) : 0u) |
              (t.wide ? static_cast<dev::u32>(dev::TEXTURE_WIDE) : 0u) |
              (levels << dev::TEXTURE_LEVELS_SHIFT);
    flat.textures.push_back(d);
    flat.texels.insert(flat.texels.end(), t.texels.begin(), t.texels.end());
    flat.texels.insert(flat.texels.end(), mips.begin(), mips.end());
    flat.mip_texels += mips.size();
  }
  const Bounds b = scene.bounds();
  const glm::vec3 c = b.empty() ? glm::vec3(0.0f) : b.center();
  flat.info.num_textures = static_cast<dev::u32>(flat.textures.size());
  for (int i = 0; i < 3; ++i) flat.info.bounds_center[i] = c[i];
  flat.info.bounds_radius = b.empty() ? 0.0f : 0.5f * glm::length(b.extent());
  build_environment(env, flat);
  build_lights(scene, flat);  // sets num_lights and env_light
  return flat;
}

namespace {

template <typename T>
cl::Buffer upload(const cl::Context& ctx, const FlatScene&, const std::vector<T>& data, const char* what) {
  const std::string name = std::string(what) + " buffer";
  return cl::Buffer::from_vector(ctx, data, CL_MEM_READ_ONLY, name.c_str());
}
cl::Buffer upload(const cl::Context& ctx, const FlatScene& flat, const dev::SceneInfo& info,
                  const char* what) {
  return upload(ctx, flat, std::vector<dev::SceneInfo>{info}, what);
}
// The lanes' rows (bvh.h's triangle_lanes), leaf after leaf in leaf order, written in pieces of
// about 4 MiB at their offsets.
cl::Buffer upload(const cl::Context& ctx, const FlatScene& flat, const TriangleLanes&, const char* what) {
  if (!cl::triangle_lanes(ctx.device())) return upload(ctx, flat, std::vector<float>{0.0f}, what);
  const std::string name = std::string(what) + " buffer";
  const size_t total = 9 * flat.triangles.size() + kTriangleLanesPadding;
  cl::Buffer buffer(ctx, total * sizeof(float), CL_MEM_READ_ONLY, nullptr, name.c_str());
  constexpr size_t kPiece = size_t(1) << 20;  // floats
  std::vector<float> piece;
  size_t piece_first = 0;  // the float where `piece` goes
  auto flush = [&] {
    if (!piece.empty()) buffer.write(piece.data(), piece.size() * sizeof(float), piece_first * sizeof(float));
    piece_first += piece.size();
    piece.clear();
  };
  piece.reserve(kPiece + 9 * 64);
  for (const LeafRange& leaf : wide_leaves(flat.nodes)) {
    if (piece.size() >= kPiece) flush();
    const size_t at = piece.size();
    piece.resize(at + 9 * size_t(leaf.count));
    leaf_lanes(leaf, flat.triangles.data(), flat.vertices.data(), piece.data() + at);
  }
  piece.resize(piece.size() + kTriangleLanesPadding, 0.0f);
  flush();  // the leaves tile the triangles (BvhBuild.TriangleLanesHoldEachLeafsPositions)
  return buffer;
}

}  // namespace

#define CLPT_SCENE_UPLOAD(type, name, what) name##_(upload(ctx, flat, flat.name, what)),
SceneBuffers::SceneBuffers(const cl::Context& ctx, const FlatScene& flat)
    : SCENE_ARRAYS(CLPT_SCENE_UPLOAD) num_lights_(static_cast<uint32_t>(flat.lights.size())),
      num_triangles_(static_cast<uint32_t>(flat.triangles.size())) {}
#undef CLPT_SCENE_UPLOAD

cl_uint SceneBuffers::bind(cl::Kernel& kernel, cl_uint first) const {
#define CLPT_SCENE_BIND(type, name, what) kernel.arg(first++, name##_);
  SCENE_ARRAYS(CLPT_SCENE_BIND)
#undef CLPT_SCENE_BIND
  return first;
}

size_t SceneBuffers::device_bytes() const {
  size_t bytes = 0;
#define CLPT_SCENE_BYTES(type, name, what) bytes += name##_.size();
  SCENE_ARRAYS(CLPT_SCENE_BYTES)
#undef CLPT_SCENE_BYTES
  return bytes;
}

}  // namespace clpt
