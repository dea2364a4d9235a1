// Bounding volume hierarchy over triangles: a binned SAH build (Wald 2007, "On fast
// Construction of SAH-based Bounding Volume Hierarchies") flattened depth-first into 32-byte
// binary nodes (BvhNode), then collapsed into the 4-wide dev::BvhNode4 the kernels traverse
// (kernels/bvh/intersect.cl).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/bvh_constants.h"
#include "shared/scene_types.h"

namespace clpt {

// The binary build's 32-byte node, depth-first order: an interior node's first child follows
// it. count > 0: a leaf holding triangles [offset, offset + count) (leaf order); count <= 0: an
// interior node, offset = the index of its second child, split axis = -count.
struct BvhNode {
  float bmin[3];
  int32_t offset;
  float bmax[3];
  int32_t count;
};

static_assert(sizeof(BvhNode) == 32, "BvhNode must stay 32 bytes");
static_assert(sizeof(dev::BvhNode4) == 128, "BvhNode4 must stay 128 bytes");
static_assert(sizeof(dev::Triangle) == 16, "Triangle must stay 16 bytes");
static_assert(sizeof(dev::Vertex) == 32, "Vertex must stay 32 bytes");

// Triangles per leaf at most, by how the devices test a leaf's triangles: where they test
// them four at a time in float4 lanes (CPU devices, CLPT_TRIANGLE_LANES 4; cl::triangle_lanes),
// leaves of up to 8 (two lane groups) trace faster than leaves of 4 with the node level more
// they need (docs/BENCHMARKS.md, session 45); devices that test one triangle at a time (GPUs)
// keep 4, the size measured there.
constexpr int kMaxLeafLanes = 8;
constexpr int kMaxLeafOneAtATime = 4;

struct BvhBuildOptions {
  int max_leaf_size = kMaxLeafOneAtATime;  // (exceeded only when centroids coincide at depth limit)
  int bins = 16;          // SAH bins per axis (clamped to [2, 256])
};

// Layout (see kernels/shared/scene_types.h): nodes[0] is the root; an interior node's first
// child follows it and `offset` is its second child, split axis = -count; a leaf
// (count > 0) holds leaf-order triangles [offset, offset + count).
//
// Depth never exceeds CLPT_BVH_MAX_DEPTH: where a SAH split would let a subtree outgrow the
// levels left, the builder splits at the object median instead, and triangles whose
// centroids all coincide are split at the median of their order.
//
// An empty input gives one leaf with an empty box (bmin = +inf, bmax = -inf), offset 0 and
// count 1, and an empty triangle_order. No ray enters an empty box, and the kernels test
// the root box before anything else, so that phantom triangle is never read. Host code
// should check triangle_order.empty() instead of walking such a tree.
struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<uint32_t> triangle_order;  // leaf-order slot i holds original triangle triangle_order[i]
  int depth = 0;                         // levels, root = 1
  // What the kernels traverse: the same tree collapsed to 4 children a node (collapse_bvh4).
  std::vector<dev::BvhNode4> wide;
  int wide_depth = 0;

  bool empty() const { return triangle_order.empty(); }
};

// Builds the BVH with all hardware threads. Triangles may be degenerate (zero area,
// collinear, repeated vertices); positions are expected finite (non-finite ones do not
// crash the build but give boxes no ray enters reliably). Throws clpt::Error(BadInput) for
// an index out of range or more than 2^31 - 1 triangles.
Bvh build_bvh(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
              const BvhBuildOptions& options = {});

// The binary tree `nodes` (Bvh::nodes' layout) as a 4-wide one (dev::BvhNode4), as Embree's
// and most CPU and GPU traversals use (Wald, Benthin, Boulos 2008; Dammertz et al. 2008): from
// the root down, a wide node takes its binary node's two children and, while it has fewer
// than four, opens them (those that are inner) into theirs, then the inner child of the
// largest surface area. The leaves and their triangle ranges are the binary tree's. Every
// inner child a wide node keeps lies at least two binary levels below it, so the wide depth
// (returned in *depth) is at most half the binary one (at least 1): the kernels' stack of
// CLPT_BVH4_STACK entries holds three a level.
std::vector<dev::BvhNode4> collapse_bvh4(const std::vector<BvhNode>& nodes, int* depth);

// The leaves' triangle positions as the traversal's float4 lanes read them on CPU devices
// (CLPT_TRIANGLE_LANES 4: kernels/bvh/intersect.cl's intersect_triangle4): a leaf's triangles
// [first, first + count), leaf order, taken four at a time, i = first, first + 4, ...; the
// group of m <= 4 triangles from leaf-order triangle i is stored from float 9 i on, as nine
// rows of m floats, row 3 v + a holding axis a (x, y, z) of vertex v of each of its
// triangles. So a lane needs no vertex index and no gather: row r of the group is one float4
// read at 9 i + r m, and a read of a shorter group runs into what follows it, which the lane
// mask drops (3 floats of zeros end the array for the last group's). 9 floats a triangle; the
// floats are the vertex array's own, so each lane's hit is bit for bit the indexed test's.
struct LeafRange {
  uint32_t first, count;
};
inline constexpr size_t kTriangleLanesPadding = 3;

// The leaves of the 4-wide tree, sorted by first: they tile the leaf-order triangles.
std::vector<LeafRange> wide_leaves(const std::vector<dev::BvhNode4>& wide);

// One leaf's 9 * count floats, to `out` (the array's float 9 * first).
void leaf_lanes(const LeafRange& leaf, const dev::Triangle* triangles, const dev::Vertex* vertices,
                float* out);

// The whole array: 9 floats a triangle and the padding (render/scene_buffers streams it to the
// device in pieces instead).
std::vector<float> triangle_lanes(const std::vector<dev::BvhNode4>& wide,
                                  const std::vector<dev::Triangle>& triangles,
                                  const std::vector<dev::Vertex>& vertices);

}  // namespace clpt
