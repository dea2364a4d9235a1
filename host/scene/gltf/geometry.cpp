// The glTF loader's geometry: mesh primitives (attributes, indices, triangle modes, generated
// tangents) read once in local space, then placed in world space per node and per
// EXT_mesh_gpu_instancing instance, against the vertex, triangle and memory limits.
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>

#include "scene/gltf/gltf_internal.h"
#include "scene/tangents.h"
#include "util/log.h"

namespace clpt::gltf {

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

const LocalPrimitive& Converter::local_primitive(int mesh, int prim) {
  auto key = std::make_pair(mesh, prim);
  auto found = cache_.find(key);
  if (found != cache_.end()) return found->second;

  const tinygltf::Primitive& p = m_.meshes[size_t(mesh)].primitives[size_t(prim)];
  const std::string where = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(prim);
  LocalPrimitive lp;
  auto draco = p.extensions.find("KHR_draco_mesh_compression");
  if (draco != p.extensions.end()) decode_draco(p, draco->second, where);

  auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) fail(where + " has no POSITION attribute");
  {
    std::vector<float> v = read_values(pos_it->second, "POSITION of " + where, TINYGLTF_TYPE_VEC3, Components::Position);
    const size_t n = v.size() / 3;
    lp.positions.resize(n);
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 q(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      if (!finite(q))
        fail(where + ": POSITION " + std::to_string(i) + " is not finite (" + number(q.x) + ", " + number(q.y) +
           ", " + number(q.z) + ")");
      lp.positions[i] = glm::vec3(q);
    }
  }
  const size_t nverts = lp.positions.size();
  if (nverts > limits_.vertices)
    fail(where + " has " + std::to_string(nverts) + " vertices, more than the limit of " + std::to_string(limits_.vertices) +
         " (--limit vertices=N)");
  auto check_count = [&](const char* name, size_t n) {
    if (n != nverts)
      fail(where + " has " + std::to_string(n) + " " + name + " values but " + std::to_string(nverts) + " positions");
  };
  auto nrm_it = p.attributes.find("NORMAL");
  if (nrm_it != p.attributes.end()) {
    std::vector<float> v = read_values(nrm_it->second, "NORMAL of " + where, TINYGLTF_TYPE_VEC3, Components::Direction);
    check_count("NORMAL", v.size() / 3);
    lp.normals.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec3 q(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      lp.normals[i] = finite(q) ? glm::vec3(q) : glm::vec3(0.0f);
    }
  }
  // A UV set, when the primitive has it: non-finite coordinates become (0, 0).
  const auto read_uv_set = [&](const char* name, std::vector<glm::vec2>& out) {
    auto it = p.attributes.find(name);
    if (it == p.attributes.end()) return;
    std::vector<float> v = read_values(it->second, std::string(name) + " of " + where,
                                       TINYGLTF_TYPE_VEC2, Components::TexCoord);
    check_count(name, v.size() / 2);
    out.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec2 q(v[2 * i], v[2 * i + 1]);
      out[i] = std::isfinite(q.x) && std::isfinite(q.y) ? glm::vec2(q) : glm::vec2(0.0f);
    }
  };
  read_uv_set("TEXCOORD_0", lp.uvs);
  read_uv_set("TEXCOORD_1", lp.uvs1);
  auto tan_it = p.attributes.find("TANGENT");
  if (tan_it != p.attributes.end()) {
    std::vector<float> v = read_values(tan_it->second, "TANGENT of " + where, TINYGLTF_TYPE_VEC4, Components::Direction);
    check_count("TANGENT", v.size() / 4);
    lp.tangents.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::dvec3 t(v[4 * i], v[4 * i + 1], v[4 * i + 2]);
      const double len = glm::length(t);
      // A tangent that is not finite or zero means "no normal mapping here", not an error.
      if (finite(t) && len > 0.0 && std::isfinite(len))
        lp.tangents[i] = glm::vec4(glm::vec3(t / len), v[4 * i + 3] < 0.0f ? -1.0f : 1.0f);
    }
  }
  auto col_it = p.attributes.find("COLOR_0");
  if (col_it != p.attributes.end()) {
    if (col_it->second < 0 || size_t(col_it->second) >= m_.accessors.size())
      fail("COLOR_0 of " + where + " refers to accessor " + std::to_string(col_it->second) +
           ", which does not exist (the file has " + std::to_string(m_.accessors.size()) + ")");
    const int type = m_.accessors[size_t(col_it->second)].type == TINYGLTF_TYPE_VEC3 ? TINYGLTF_TYPE_VEC3
                                                                                      : TINYGLTF_TYPE_VEC4;
    const size_t nc = type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    std::vector<float> v = read_values(col_it->second, "COLOR_0 of " + where, type, Components::FloatOrUNorm);
    check_count("COLOR_0", v.size() / nc);
    lp.colors.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) {
      glm::vec4 c(1.0f);
      for (size_t k = 0; k < nc; ++k) {
        const float x = v[nc * i + k];
        c[int(k)] = std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 1.0f;
      }
      lp.colors[i] = c;
    }
  }

  std::vector<uint32_t> idx;
  if (const int indices = indices_accessor(p); indices >= 0) {
    idx = read_indices(indices, "indices of " + where);
    for (size_t i = 0; i < idx.size(); ++i)
      if (idx[i] >= nverts)
        fail(where + ": index " + std::to_string(idx[i]) + " (entry " + std::to_string(i) +
             " of accessor " + std::to_string(indices) + ") is not less than the vertex count " +
             std::to_string(nverts));
  } else {
    idx.resize(nverts);
    for (size_t i = 0; i < nverts; ++i) idx[i] = uint32_t(i);
  }

  const size_t n = idx.size();
  const uint64_t ntri = p.mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
  if (ntri > limits_.triangles)
    fail(where + " has " + std::to_string(ntri) + " triangles, more than the limit of " + std::to_string(limits_.triangles) +
         " (--limit triangles=N)");
  switch (p.mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (n % 3 != 0) ++leftover_primitives_;
      lp.triangles.reserve(n / 3);
      for (size_t i = 0; i + 2 < n; i += 3) lp.triangles.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      // glTF: triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}): every other one flips so all
      // keep the winding of the first.
      if (n >= 3) lp.triangles.reserve(n - 2);
      for (size_t i = 0; i + 2 < n; ++i)
        lp.triangles.emplace_back(idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      // glTF: triangle i is (v_{i+1}, v_{i+2}, v_0).
      if (n >= 3) lp.triangles.reserve(n - 2);
      for (size_t i = 0; i + 2 < n; ++i) lp.triangles.emplace_back(idx[i + 1], idx[i + 2], idx[0]);
      break;
    default:
      fail(where + " has mode " + std::to_string(p.mode) + ", which is not a triangle mode");
  }
  // Normal maps (the base's, the clearcoat's) and an anisotropic BSDF need tangents: generate
  // them from the first normal map's UV set (else the anisotropy texture's, else TEXCOORD_0)
  // when the file gives none (the material index is checked by material_for before this is
  // called).
  const Material* pm = p.material >= 0 && size_t(p.material) < scene_.materials.size()
                           ? &scene_.materials[size_t(p.material)]
                           : nullptr;
  const TextureRef* normal_map = !pm                                      ? nullptr
                                 : pm->normal_texture.used()              ? &pm->normal_texture
                                 : pm->clearcoat_normal_texture.used() && pm->clearcoat > 0.0f
                                     ? &pm->clearcoat_normal_texture
                                     : nullptr;
  const bool needs_tangents = pm && (normal_map || pm->anisotropy_strength > 0.0f);
  if (lp.tangents.empty() && needs_tangents) {
    const bool set1 = normal_map ? normal_map->texcoord == 1
                                 : pm->anisotropy_texture.used() && pm->anisotropy_texture.texcoord == 1;
    const std::vector<glm::vec2>& uv = set1 ? lp.uvs1 : lp.uvs;
    if (uv.empty()) {
      log::warn(display_ + ": " + where + " has " +
                (normal_map ? "a normal map" : "an anisotropic material") + " but no TEXCOORD_" +
                (set1 ? "1" : "0") + "; " + (normal_map ? "the normal map is ignored" : "it renders isotropic"));
    } else {
      lp.tangents = generate_tangents(lp.positions, lp.normals, uv, lp.triangles);
      log::verbose(display_ + ": " + where + ": generated tangents (no TANGENT attribute)");
    }
  }
  return cache_.emplace(key, std::move(lp)).first->second;
}

// The host memory the geometry will need up to upload (scene arrays, flattened arrays, BVH
// build), so that a small file cannot make clpt allocate until the system kills it.
void Converter::check_geometry_memory(uint64_t v, uint64_t t) const {
  if (v > limits_.vertices)
    fail("the scene has more than " + std::to_string(limits_.vertices) + " vertices (the limit; --limit vertices=N)");
  if (t > limits_.triangles)
    fail("the scene has more than " + std::to_string(limits_.triangles) + " triangles (the limit; --limit triangles=N)");
  const u128 need = u128(v) * kHostBytesPerVertex + u128(t) * kHostBytesPerTriangle;
  std::string which;
  const uint64_t budget = limits_.memory_budget(file_bytes_, &which);
  if (need > budget)
    fail("the scene needs about " + bytes_text(uint64_t(std::min<u128>(need, ~uint64_t{0}))) + " of memory for " +
         std::to_string(v) + " vertices and " + std::to_string(t) +
         " triangles (after instancing), more than the budget of " + bytes_text(budget) + " (" + which + ")");
}

void Converter::add_instance(const LocalPrimitive& lp, const glm::dmat4& world, uint32_t material, int node,
                             int mesh, int prim) {
  check_geometry_memory(scene_.positions.size() + lp.positions.size(),
                        scene_.triangles.size() + lp.triangles.size());
  if (lp.triangles.empty()) return;

  const glm::dmat3 linear(world);
  const double det = glm::determinant(linear);
  glm::dmat3 normal_matrix = glm::inverseTranspose(linear);
  bool normals_ok = std::isfinite(det) && det != 0.0;
  for (int c = 0; c < 3 && normals_ok; ++c) normals_ok = finite(normal_matrix[c]);

  const uint32_t base = uint32_t(scene_.positions.size());
  for (size_t i = 0; i < lp.positions.size(); ++i) {
    glm::dvec3 p = glm::dvec3(world * glm::dvec4(glm::dvec3(lp.positions[i]), 1.0));
    glm::vec3 pf(p);
    if (!finite(glm::dvec3(pf)))
      fail("node " + std::to_string(node) + " transforms mesh " + std::to_string(mesh) + " primitive " +
           std::to_string(prim) + " to non-finite positions");
    scene_.positions.push_back(pf);
    glm::vec3 n(0.0f);
    if (normals_ok && !lp.normals.empty()) {
      glm::dvec3 t = normal_matrix * glm::dvec3(lp.normals[i]);
      double len = glm::length(t);
      if (std::isfinite(len) && len > 0.0) n = glm::vec3(t / len);
      if (!finite(glm::dvec3(n))) n = glm::vec3(0.0f);
    }
    scene_.normals.push_back(n);
    scene_.uvs.push_back(lp.uvs.empty() ? glm::vec2(0.0f) : lp.uvs[i]);
  }
  // Optional attributes: the scene's array stays empty until some primitive has one, then
  // holds a default for every vertex that has none.
  auto append = [&](auto& dst, const auto& src, auto def, auto&& convert) {
    if (src.empty() && dst.empty()) return;
    if (dst.empty()) dst.assign(base, def);
    for (size_t i = 0; i < lp.positions.size(); ++i) dst.push_back(src.empty() ? def : convert(src[i]));
  };
  const bool mirror = det < 0.0;
  append(scene_.uvs1, lp.uvs1, glm::vec2(0.0f), [](const glm::vec2& v) { return v; });
  append(scene_.colors, lp.colors, glm::vec4(1.0f), [](const glm::vec4& v) { return v; });
  // Tangents follow the surface: the linear part, not the normal matrix; a mirror flips the
  // handedness (cross(n', t') turns against the transformed bitangent).
  append(scene_.tangents, lp.tangents, glm::vec4(0.0f), [&](const glm::vec4& t) {
    if (t == glm::vec4(0.0f)) return t;
    const glm::dvec3 v = linear * glm::dvec3(t);
    const double len = glm::length(v);
    if (!(len > 0.0) || !std::isfinite(len)) return glm::vec4(0.0f);
    return glm::vec4(glm::vec3(v / len), mirror ? -t.w : t.w);
  });
  for (const glm::uvec3& t : lp.triangles) {
    glm::uvec3 w = t + glm::uvec3(base);
    if (mirror) std::swap(w.y, w.z);
    scene_.triangles.push_back(w);
    scene_.triangle_materials.push_back(material);
  }
}

// EXT_mesh_gpu_instancing: one transform per instance (TRS from accessors), applied before
// the node's own world transform. Empty when the node has no such extension.
std::vector<glm::dmat4> Converter::instance_transforms(int node, uint64_t vertices, uint64_t triangles) {
  const tinygltf::Node& n = m_.nodes[size_t(node)];
  auto ext = n.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == n.extensions.end()) return {};
  const std::string where = "node " + std::to_string(node) + " EXT_mesh_gpu_instancing";
  if (!ext->second.IsObject() || !ext->second.Has("attributes") || !ext->second.Get("attributes").IsObject())
    fail(where + " has no attributes object");
  const tinygltf::Value& attrs = ext->second.Get("attributes");
  std::vector<float> t, r, s;
  uint64_t count = 0;
  bool any = false;
  auto read = [&](const char* name, int type, Components allowed, std::vector<float>* out) {
    if (!attrs.Has(name)) return;
    const tinygltf::Value& v = attrs.Get(name);
    if (!v.IsInt()) fail(where + " attribute " + name + " is not an accessor index");
    *out = read_values(v.GetNumberAsInt(), std::string(name) + " of " + where, type, allowed);
    uint64_t c = out->size() / size_t(type_components(type));
    if (any && c != count)
      fail(where + " attributes have different counts (" + std::to_string(count) + " and " + std::to_string(c) + ")");
    count = c;
    any = true;
  };
  read("TRANSLATION", TINYGLTF_TYPE_VEC3, Components::Float, &t);
  read("ROTATION", TINYGLTF_TYPE_VEC4, Components::FloatOrSNorm, &r);
  read("SCALE", TINYGLTF_TYPE_VEC3, Components::Float, &s);
  if (!any) fail(where + " has none of the attributes TRANSLATION, ROTATION, SCALE");
  // Every instance's geometry against the limits before the first transform is made, let alone
  // copied (the products are below 2^60: a mesh's vertices and triangles are within their
  // limits, the instances within accessor-count).
  check_geometry_memory(scene_.positions.size() + vertices * count, scene_.triangles.size() + triangles * count);

  std::vector<glm::dmat4> out(size_t(count), glm::dmat4(1.0));
  for (size_t i = 0; i < count; ++i) {
    glm::dmat4 m(1.0);
    if (!r.empty()) {
      glm::dvec4 q(r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]);
      double len = glm::length(q);
      if (!std::isfinite(len) || len < 1e-6) fail(where + " rotation " + std::to_string(i) + " is not a unit quaternion");
      q /= len;
      const double x = q.x, y = q.y, z = q.z, w = q.w;
      m[0] = glm::dvec4(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y), 0);
      m[1] = glm::dvec4(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x), 0);
      m[2] = glm::dvec4(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y), 0);
    }
    if (!s.empty()) {
      m[0] *= s[3 * i];
      m[1] *= s[3 * i + 1];
      m[2] *= s[3 * i + 2];
    }
    if (!t.empty()) m[3] = glm::dvec4(t[3 * i], t[3 * i + 1], t[3 * i + 2], 1.0);
    if (!finite(m)) fail(where + " instance " + std::to_string(i) + " has a non-finite transform");
    out[i] = m;
  }
  return out;
}

void Converter::add_mesh(int node, int mesh, const glm::dmat4& world) {
  if (mesh < 0 || size_t(mesh) >= m_.meshes.size())
    fail("node " + std::to_string(node) + " refers to mesh " + std::to_string(mesh) +
         ", which does not exist (the file has " + std::to_string(m_.meshes.size()) + ")");
  const auto& prims = m_.meshes[size_t(mesh)].primitives;
  std::vector<const LocalPrimitive*> local(prims.size(), nullptr);  // null: points or lines
  uint64_t vertices = 0, triangles = 0;
  for (size_t pi = 0; pi < prims.size(); ++pi) {
    const tinygltf::Primitive& p = prims[pi];
    if (p.mode >= TINYGLTF_MODE_POINTS && p.mode <= TINYGLTF_MODE_LINE_STRIP) {
      ++skipped_primitives_;
      skipped_modes_.insert(p.mode);
      continue;
    }
    local[pi] = &local_primitive(mesh, int(pi));
    vertices += local[pi]->positions.size();
    triangles += local[pi]->triangles.size();
  }
  const std::vector<glm::dmat4> instances = instance_transforms(node, vertices, triangles);
  for (size_t pi = 0; pi < prims.size(); ++pi) {
    if (!local[pi]) continue;
    const std::string where = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(pi);
    const uint32_t material = material_for(prims[pi].material, where);
    if (instances.empty()) {
      add_instance(*local[pi], world, material, node, mesh, int(pi));
    } else {
      for (const glm::dmat4& inst : instances) add_instance(*local[pi], world * inst, material, node, mesh, int(pi));
    }
  }
}

}  // namespace clpt::gltf
