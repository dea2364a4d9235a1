// Left-balanced kd-tree over photon positions for k-nearest-neighbour and radius queries,
// as in Jensen (2001), "Realistic Image Synthesis Using Photon Maps": the tree is a heap
// (no pointers), each subset is split at its median on the axis of its largest extent, and
// the nearest-photon search keeps a max-heap of the k best found so far and shrinks its
// search radius to the k-th distance once that heap is full. One departure: a subtree is
// skipped by the distance from the query point to its cell (the sum of the squared
// per-axis offsets, Arya and Mount's incremental distance, 1993) rather than by the
// distance to its splitting plane alone, which is a lower bound of it; far from the
// photons (an unbounded kNN query outside the cloud) the plane test visits much of the tree:
// 4.3 ms against 0.2 ms per k = 50 query at 1M photons in a cube, 3.5 cube widths from
// its centre.
//
// Built on the host; the layout and the queries are written for a later OpenCL port (flat
// 16-byte nodes, an explicit fixed-size stack, no recursion, no allocation inside a query).
//
// Layout
// ------
// `nodes` is a heap-ordered array of n KdNodes (n = number of photons):
//   - nodes[0] is the root; node i's children are 2i + 1 and 2i + 2 where those are < n.
//     The tree is complete: every level is full except the last, which fills from the left,
//     so its height is floor(log2 n) + 1 (at most 31, since n <= kKdMaxPoints).
//   - KdNode is 16 bytes, 16-byte aligned: the photon's position (float x, y, z) and one
//     uint32 `index_axis` = photon_index << 2 | axis. A kernel reads a node as one float4 and
//     takes as_uint(w). OpenCL C:  typedef struct { float pos[3]; uint index_axis; } KdNode;
//   - photon_index is the photon's index in the caller's input array (the tree keeps a copy
//     of the positions in heap order, plus those indices; the caller's array is not
//     reordered, so power, direction etc. are fetched as photons[photon_index]. A caller
//     that wants heap-ordered payloads can permute its array by photon_index once.)
//   - axis: 0, 1, 2 = the node splits its subtree by the plane pos[axis] through its own
//     photon: every photon of the left subtree has pos[axis] <= the node's, every photon of
//     the right subtree has pos[axis] >= the node's (equal values may lie on both sides).
//     3 (kKdLeafAxis) = a leaf (2i + 1 >= n).
//
// Queries (kdtree.cpp, to be ported as they are): depth first, nearer child first, each
// node's photon examined on the way down; a far child goes on a stack of kKdMaxStack
// 16-byte entries {float offset[3]; uint node} (512 bytes of private memory), offset being
// the query point's per-axis offset from the child's cell. A stack never holds two entries
// of one level, so 30 entries suffice for 2^30 photons.
//
// Distances are squared Euclidean distances in float, computed as dx*dx + dy*dy + dz*dz;
// a cell's bound is summed in the same order, so pruning is exact in float (never drops a
// photon that the brute force would count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/photon_types.h"

namespace clpt {

// The node layout is shared with the kernels (kernels/shared/photon_types.h).
using KdNode = dev::KdNode;
static_assert(sizeof(KdNode) == 16, "KdNode must stay 16 bytes (one float4 on the device)");

constexpr uint32_t kKdLeafAxis = KD_LEAF_AXIS;
constexpr uint32_t kKdMaxPoints = 1u << 30;  // photon_index must fit in 30 bits
// Traversal stack entries: one per level below the root, at most 30 for 2^30 photons.
constexpr int kKdMaxStack = 32;

inline uint32_t kd_photon_index(const KdNode& node) { return node.index_axis >> 2; }
inline uint32_t kd_split_axis(const KdNode& node) { return node.index_axis & 3u; }

// One query result: a photon's squared distance to the query point and its input index.
struct KdNeighbor {
  float distance2;
  uint32_t index;
};

struct KdTree {
  std::vector<KdNode> nodes;  // heap order, see the layout above

  size_t size() const { return nodes.size(); }
  bool empty() const { return nodes.empty(); }
  int height() const;  // levels; 0 when empty

  // The k photons nearest to p among those within max_radius (distance2 <= max_radius^2;
  // max_radius may be +infinity), sorted by ascending distance2, into `out` (cleared first;
  // reuse it across queries to avoid allocation). Returns their count: min(k, photons
  // within max_radius). Photons at the same distance as the k-th are interchangeable: which
  // of them are returned is unspecified. k = 0, an empty tree, or a negative or NaN radius
  // give no result.
  size_t knn(const glm::vec3& p, size_t k, float max_radius, std::vector<KdNeighbor>& out) const;

  // Every photon within `radius` of p (distance2 <= radius^2) into `out` (cleared first),
  // in no particular order. Returns their count.
  size_t within(const glm::vec3& p, float radius, std::vector<KdNeighbor>& out) const;
};

// Builds the tree in O(n log n) expected time (std::nth_element at every level; the top
// levels in parallel on all hardware threads; the result does not depend on the thread
// count). Among axes of equal extent (coincident photons, a line) the split axis rotates
// with the level, so a cell bound reaches the true distance of a pile of coincident photons
// within three levels (a kNN query beside a pile of 100 000: 40 us, against 420 us when
// every split is on x). Any finite positions work, including duplicates, all points
// identical, and zero or one point.
// Throws clpt::Error(BadInput) for a non-finite position (naming its index) or more than
// kKdMaxPoints points.
KdTree build_kdtree(const std::vector<glm::vec3>& points);

}  // namespace clpt
