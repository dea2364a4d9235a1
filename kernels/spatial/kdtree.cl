/* k-nearest-neighbour search in the photon kd-tree (Jensen 2001, §6.3), the device side of
 * host/photon/kdtree.cpp: the same traversal, pruning and tie rule, so the host tests of
 * KdTree::knn describe it, and tests/photon_map_test.cpp checks that the two agree.
 *
 * The tree is a heap-ordered array of KdNodes (kernels/shared/photon_types.h). The search
 * is depth first, nearer child first, each node's photon examined on the way down; far
 * children wait on a fixed stack with their cell's per-axis offsets from the query point
 * (Arya and Mount 1993), and are skipped once the cell lies beyond the k-th distance. The k
 * best so far are a max-heap in the caller's private array, the farthest at heap[0].
 *
 * Memory, not arithmetic, is what the search waits on (a map of 10^5 to 10^6 photons, 16-byte
 * nodes in heap order, so a node's children lie far from it once below the first levels; the
 * estimate then reads its k photons, 64 bytes each, at random): each node visited fetches the
 * line of its four grandchildren (4i + 3 .. 4i + 6, one 64-byte line) while the child is
 * examined, and each photon taken into the heap is fetched for the estimate that follows
 * (CLPT_PREFETCH, CPU devices; pm on the Cornell box 1.57 to 1.67x the paths/s, docs/BENCHMARKS.md
 * session 41). */
#ifndef CLPT_PHOTON_KDTREE_CL
#define CLPT_PHOTON_KDTREE_CL

#include "core/prefetch.cl"
#include "shared/photon_types.h"

#define KD_MAX_STACK 32

typedef struct KdNeighbor {
  float d2;  /* squared distance to the query point */
  u32 index; /* photon index */
} KdNeighbor;

static inline void kd_sift_up(KdNeighbor* heap, u32 i) {
  while (i > 0u) {
    const u32 parent = (i - 1u) / 2u;
    if (heap[parent].d2 >= heap[i].d2) break;
    const KdNeighbor t = heap[parent];
    heap[parent] = heap[i];
    heap[i] = t;
    i = parent;
  }
}

static inline void kd_sift_down(KdNeighbor* heap, u32 i, u32 size) {
  for (;;) {
    const u32 l = 2u * i + 1u;
    if (l >= size) break;
    u32 c = l;
    if (l + 1u < size && heap[l + 1u].d2 > heap[l].d2) c = l + 1u;
    if (heap[c].d2 <= heap[i].d2) break;
    const KdNeighbor t = heap[c];
    heap[c] = heap[i];
    heap[i] = t;
    i = c;
  }
}

/* Whether a cell at squared distance `bound` may still hold a better photon: within the
 * radius while the heap fills, closer than the k-th distance once it is full (a photon tied
 * with the k-th would not replace it). */
static inline bool kd_reaches(float bound, float r2, u32 count, u32 capacity) {
  return count < capacity ? bound <= r2 : bound < r2;
}

/* Distances and cell bounds are summed without fused multiply-adds, as the host does: a
 * fused bound could exceed a photon's unfused distance and prune it, and the host tests'
 * exact agreement would not hold (tests/photon_map_test.cpp). */
static inline float kd_cell_distance2(float4 c) {
#pragma OPENCL FP_CONTRACT OFF
  return c.x * c.x + c.y * c.y + c.z * c.z;
}

/* The min(k, photons within max_r2) photons nearest to p, into heap[0, count) (heap order,
 * not sorted: heap[0] is the farthest). heap must hold k entries. Returns count. photons:
 * the photon array the indices point into, whose entries are fetched ahead as they are kept
 * (0: none). */
static inline u32 kd_knn(__global const KdNode* nodes, u32 n, float3 p, u32 k, float max_r2,
                         KdNeighbor* heap, __global const Photon* photons) {
#pragma OPENCL FP_CONTRACT OFF
  if (n == 0u || k == 0u || !(max_r2 >= 0.0f)) return 0u;
  const u32 capacity = min(k, n);
  u32 count = 0u;
  float r2 = max_r2;
  float4 stack[KD_MAX_STACK]; /* xyz: cell offsets, w: node index as bits */
  int top = 0;
  float4 cur = (float4)(0.0f, 0.0f, 0.0f, as_float(0u));
  for (;;) {
    u32 i = as_uint(cur.w);
    while (i < n) {
      const float4 node = vload4(0, (__global const float*)(nodes + i));
      CLPT_PREFETCH(nodes + 4u * i + 3u); /* the grandchildren, past the end for a leaf */
      const float dx = p.x - node.x, dy = p.y - node.y, dz = p.z - node.z;
      const float d2 = dx * dx + dy * dy + dz * dz;
      const u32 index_axis = as_uint(node.w);
      if (d2 <= r2) {
        if (count < capacity) {
          heap[count].d2 = d2;
          heap[count].index = index_axis >> 2;
          if (photons) CLPT_PREFETCH(photons + (index_axis >> 2));
          kd_sift_up(heap, count);
          if (++count == capacity) r2 = heap[0].d2;
        } else if (d2 < heap[0].d2) {
          heap[0].d2 = d2;
          heap[0].index = index_axis >> 2;
          if (photons) CLPT_PREFETCH(photons + (index_axis >> 2));
          kd_sift_down(heap, 0u, capacity);
          r2 = heap[0].d2;
        }
      }
      const u32 axis = index_axis & 3u;
      if (axis == KD_LEAF_AXIS) break;
      const float d = axis == 0u ? dx : (axis == 1u ? dy : dz);
      const u32 near = d < 0.0f ? 2u * i + 1u : 2u * i + 2u;
      const u32 far = d < 0.0f ? 2u * i + 2u : 2u * i + 1u;
      if (far < n) {
        float4 f = cur;
        if (axis == 0u) f.x = d;
        else if (axis == 1u) f.y = d;
        else f.z = d;
        f.w = as_float(far);
        if (kd_reaches(kd_cell_distance2(f), r2, count, capacity) && top < KD_MAX_STACK)
          stack[top++] = f;
      }
      i = near;
    }
    while (top > 0 && !kd_reaches(kd_cell_distance2(stack[top - 1]), r2, count, capacity)) --top;
    if (top == 0) break;
    cur = stack[--top];
  }
  return count;
}

#endif
