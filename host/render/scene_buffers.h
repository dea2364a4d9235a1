// The scene flattened into device buffers of the structs in kernels/shared/scene_types.h.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "cl/buffer.h"
#include "cl/program.h"
#include "io/image.h"
#include "render/light_table.h"
#include "scene/scene.h"
#include "shared/scene_arrays.h"
#include "shared/scene_types.h"

namespace clpt {

// The leaves' positions for the traversal's float4 lanes (bvh.h's triangle_lanes), which only
// the kernels built with CLPT_TRIANGLE_LANES 4 read. Nothing is held here: SceneBuffers writes
// them from nodes, triangles and vertices straight into the buffer of such a device
// (cl::triangle_lanes), a piece at a time, so the host never holds a second copy; other
// devices get one float (36 bytes a triangle that a GPU would not use).
struct TriangleLanes {};

// The host-side arrays, before upload: what the device buffers will hold.
struct FlatScene {
  std::vector<dev::BvhNode4> nodes;
  std::vector<dev::Triangle> triangles;  // leaf order
  std::vector<dev::Vertex> vertices;
  TriangleLanes tri_lanes;                     // made at upload (CPU devices), see above
  std::vector<dev::VertexExtra> vertex_extra;  // empty unless the scene has tangents, UV1 or colours
  std::vector<dev::Material> materials;
  std::vector<dev::Texture> textures;
  std::vector<uint32_t> texels;                // all textures' texel words (one an RGBA8 texel,
                                               // two a 16-bit one), each texture's mip levels
                                               // after its own (render/mipmaps.h)
  size_t mip_texels = 0;                       // of those words, the mip levels' (levels 1, 2, ...)
  std::vector<dev::Light> lights;              // every light, with the alias table
  std::vector<int32_t> triangle_light;         // per leaf-order triangle: light index or -1
  std::vector<float> env_texels;               // environment map, RGBA float (4 per texel)
  std::vector<float> env_cdf;                  // its sampling distribution
  dev::SceneInfo info{};
  int bvh_depth = 0;
  uint32_t emissive_triangles = 0;             // lights of type LIGHT_TRIANGLE
  uint32_t punctual_lights = 0;                // point, spot and directional
  double total_emitted_power = 0.0;            // sum of the lights' selection weights
  double env_integral = 0.0;                   // integral over the sphere of the environment's
                                               // luminance, env_scale included
};

// mipmaps: each texture with its mip chain (render/mipmaps.h), else level 0 alone.
FlatScene flatten_scene(const Scene& scene, const Bvh& bvh, const Environment& env = {}, bool mipmaps = true);

// The BVH leaf size for this device's kernels: kMaxLeafLanes where they test a leaf's
// triangles in lanes (cl::triangle_lanes, whose positions this file uploads), else
// kMaxLeafOneAtATime. A tree shared by several devices takes the smallest of theirs.
int bvh_max_leaf(const cl::DeviceInfo& device);

class SceneBuffers {
 public:
  SceneBuffers(const cl::Context& ctx, const FlatScene& flat);

  // Binds the scene arguments in the order of SCENE_ARRAYS (kernels/shared/scene_arrays.h,
  // the kernels' SCENE_KERNEL_ARGS), starting at argument `first`; returns the next free index.
  cl_uint bind(cl::Kernel& kernel, cl_uint first = 0) const;

  uint32_t num_lights() const { return num_lights_; }
  uint32_t num_triangles() const { return num_triangles_; }
  size_t device_bytes() const;
  size_t texture_bytes() const { return texels_.size() + textures_.size(); }

 private:
#define CLPT_SCENE_BUFFER(type, name, what) cl::Buffer name##_;
  SCENE_ARRAYS(CLPT_SCENE_BUFFER)
#undef CLPT_SCENE_BUFFER
  uint32_t num_lights_ = 0;
  uint32_t num_triangles_ = 0;
};

}  // namespace clpt
