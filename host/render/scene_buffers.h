// The scene flattened into device buffers of the structs in kernels/shared/scene_types.h.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "cl/buffer.h"
#include "cl/program.h"
#include "scene/scene.h"
#include "shared/scene_types.h"

namespace clpt {

// The host-side arrays, before upload: what the device buffers will hold.
struct FlatScene {
  std::vector<dev::BvhNode> nodes;
  std::vector<dev::Triangle> triangles;  // leaf order
  std::vector<dev::Vertex> vertices;
  std::vector<dev::Material> materials;
  std::vector<dev::Emitter> emitters;    // emissive triangles with the alias table
  std::vector<int32_t> triangle_emitter; // per leaf-order triangle: emitter index or -1
  int bvh_depth = 0;
  double total_emitted_power = 0.0;      // sum over emitters of luminance(Le) * area * pi * sides
};

// Emitter selection probabilities proportional to luminance(Le) x area x sides, packed
// with Vose's alias method so the kernel picks one in O(1).
void build_emitters(const Scene& scene, FlatScene& flat);

FlatScene flatten_scene(const Scene& scene, const Bvh& bvh);

class SceneBuffers {
 public:
  SceneBuffers(const cl::Context& ctx, const FlatScene& flat);

  // Binds the scene arguments in the order of scene_view() in kernels/core/scene_view.cl,
  // starting at argument `first`; returns the next free argument index.
  cl_uint bind(cl::Kernel& kernel, cl_uint first = 0) const;

  uint32_t num_emitters() const { return num_emitters_; }
  size_t device_bytes() const;

 private:
  cl::Buffer nodes_, triangles_, vertices_, materials_, emitters_, triangle_emitter_;
  uint32_t num_emitters_ = 0;
};

}  // namespace clpt
