#include "render/scene_buffers.h"

#include <cmath>

namespace clpt {
namespace {

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

dev::Material to_device(const Material& m) {
  dev::Material d{};
  for (int i = 0; i < 4; ++i) d.base_color[i] = m.base_color[i];
  for (int i = 0; i < 3; ++i) d.emission[i] = m.emission[i];
  d.metallic = m.metallic;
  d.roughness = m.roughness;
  d.flags = 0u;
  if (m.double_sided) d.flags |= dev::MATERIAL_DOUBLE_SIDED;
  if (m.emission.x > 0.0f || m.emission.y > 0.0f || m.emission.z > 0.0f)
    d.flags |= dev::MATERIAL_EMISSIVE;
  return d;
}

}  // namespace

void build_emitters(const Scene& scene, FlatScene& flat) {
  // Power of every emissive triangle, in leaf order.
  std::vector<double> power;
  flat.emitters.clear();
  flat.triangle_emitter.assign(flat.triangles.size(), -1);
  for (size_t i = 0; i < flat.triangles.size(); ++i) {
    const dev::Triangle& t = flat.triangles[i];
    const Material& m = scene.materials[t.material];
    const float lum = luminance(m.emission);
    if (!(lum > 0.0f)) continue;
    const glm::vec3 p0 = scene.positions[t.v[0]], p1 = scene.positions[t.v[1]],
                    p2 = scene.positions[t.v[2]];
    const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    const double p = lum * area * M_PI * (m.double_sided ? 2.0 : 1.0);
    flat.triangle_emitter[i] = static_cast<int32_t>(flat.emitters.size());
    flat.emitters.push_back(dev::Emitter{static_cast<dev::u32>(i), 0.0f, 1.0f, 0u});
    power.push_back(p);
  }
  const size_t n = flat.emitters.size();
  double total = 0.0;
  for (double p : power) total += p;
  flat.total_emitted_power = total;
  if (n == 0) return;

  // Vose's alias method: slot i keeps itself with probability threshold[i], else its alias.
  std::vector<double> scaled(n);
  std::vector<size_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    flat.emitters[i].pdf_select = static_cast<float>(power[i] / total);
    scaled[i] = power[i] / total * static_cast<double>(n);
    (scaled[i] < 1.0 ? small : large).push_back(i);
  }
  while (!small.empty() && !large.empty()) {
    const size_t s = small.back(), l = large.back();
    small.pop_back();
    flat.emitters[s].alias_threshold = static_cast<float>(scaled[s]);
    flat.emitters[s].alias = static_cast<dev::u32>(l);
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Whatever is left has probability 1 up to rounding.
  for (size_t i : small) flat.emitters[i].alias_threshold = 1.0f, flat.emitters[i].alias = i;
  for (size_t i : large) flat.emitters[i].alias_threshold = 1.0f, flat.emitters[i].alias = i;
}

FlatScene flatten_scene(const Scene& scene, const Bvh& bvh) {
  FlatScene flat;
  flat.nodes = bvh.nodes;
  flat.bvh_depth = bvh.depth;
  flat.triangles.resize(bvh.triangle_order.size());
  for (size_t i = 0; i < bvh.triangle_order.size(); ++i) {
    const uint32_t src = bvh.triangle_order[i];
    const glm::uvec3& t = scene.triangles[src];
    flat.triangles[i] = dev::Triangle{{t.x, t.y, t.z}, scene.triangle_materials[src]};
  }
  flat.vertices.resize(scene.positions.size());
  for (size_t i = 0; i < scene.positions.size(); ++i) {
    dev::Vertex& v = flat.vertices[i];
    const glm::vec3 p = scene.positions[i];
    const glm::vec3 n = i < scene.normals.size() ? scene.normals[i] : glm::vec3(0.0f);
    const glm::vec2 uv = i < scene.uvs.size() ? scene.uvs[i] : glm::vec2(0.0f);
    v = dev::Vertex{{p.x, p.y, p.z}, uv.x, {n.x, n.y, n.z}, uv.y};
  }
  flat.materials.reserve(scene.materials.size());
  for (const Material& m : scene.materials) flat.materials.push_back(to_device(m));
  build_emitters(scene, flat);
  return flat;
}

SceneBuffers::SceneBuffers(const cl::Context& ctx, const FlatScene& flat)
    : nodes_(cl::Buffer::from_vector(ctx, flat.nodes, CL_MEM_READ_ONLY, "BVH node buffer")),
      triangles_(cl::Buffer::from_vector(ctx, flat.triangles, CL_MEM_READ_ONLY, "triangle buffer")),
      vertices_(cl::Buffer::from_vector(ctx, flat.vertices, CL_MEM_READ_ONLY, "vertex buffer")),
      materials_(cl::Buffer::from_vector(ctx, flat.materials, CL_MEM_READ_ONLY, "material buffer")),
      emitters_(cl::Buffer::from_vector(ctx, flat.emitters, CL_MEM_READ_ONLY, "emitter buffer")),
      triangle_emitter_(cl::Buffer::from_vector(ctx, flat.triangle_emitter, CL_MEM_READ_ONLY,
                                                "triangle emitter buffer")),
      num_emitters_(static_cast<uint32_t>(flat.emitters.size())) {}

cl_uint SceneBuffers::bind(cl::Kernel& kernel, cl_uint first) const {
  return kernel.args(first, nodes_, triangles_, vertices_, materials_, emitters_, triangle_emitter_,
                     num_emitters_);
}

size_t SceneBuffers::device_bytes() const {
  return nodes_.size() + triangles_.size() + vertices_.size() + materials_.size() +
         emitters_.size() + triangle_emitter_.size();
}

}  // namespace clpt
