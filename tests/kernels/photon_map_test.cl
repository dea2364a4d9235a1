/* Kernels for tests/photon_map_test.cpp: the photon kd-tree's kNN search
 * (kernels/spatial/kdtree.cl) and the SPPM hash grid (kernels/spatial/hash_grid.cl). */
#include "spatial/hash_grid.cl"
#include "spatial/kdtree.cl"
#include "shared/render_types.h"

/* kd_knn for query point queries[i].xyz with max_r2 = queries[i].w; its heap (in heap
 * order, as kd_knn leaves it) goes to out[i * k, i * k + counts[i]). k <= PM_KNN_MAX, the
 * size of the private heap, as in pm_radiance. */
__kernel void knn_queries(__global const KdNode* nodes, u32 n, __global const float4* queries,
                          u32 count, u32 k, __global u32* counts, __global KdNeighbor* out) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  KdNeighbor heap[PM_KNN_MAX];
  const u32 found = kd_knn(nodes, n, queries[i].xyz, k, queries[i].w, heap, 0);
  counts[i] = found;
  for (u32 j = 0; j < found; ++j) out[(size_t)i * k + j] = heap[j];
}

/* sppm_grid_insert's body: photon i into the grid. */
__kernel void grid_insert_photons(__global const Photon* photons, u32 count, float inv_cell,
                                  u32 mask, volatile __global u32* heads, __global u32* next) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  grid_insert(photons, i, inv_cell, mask, heads, next);
}

/* The photons within queries[i].w of queries[i].xyz, found by walking the grid as
 * sppm_gather does (cells from grid_cell(x - r) to grid_cell(x + r), each bucket's list,
 * photons of other cells skipped): their number, and the sums of index + 1 and of its
 * square, which the host compares with brute force. The distance is summed as the host's
 * dx*dx + dy*dy + dz*dz without contraction (sppm_gather's dot() may round differently),
 * so a photon on the sphere is in or out on both sides alike. */
__kernel void grid_gather(__global const Photon* photons, __global const u32* heads,
                          __global const u32* next, float inv_cell, u32 mask,
                          __global const float4* queries, u32 count, __global u32* counts,
                          __global ulong* sums, __global ulong* square_sums) {
#pragma OPENCL FP_CONTRACT OFF
  const u32 i = get_global_id(0);
  if (i >= count) return;
  const float3 x = queries[i].xyz;
  const float r = queries[i].w, r2 = r * r;
  const int3 lo = grid_cell(x - (float3)(r), inv_cell), hi = grid_cell(x + (float3)(r), inv_cell);
  u32 m = 0;
  ulong sum = 0, square_sum = 0;
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const int3 c = (int3)(cx, cy, cz);
        for (u32 e = heads[grid_bucket(c, mask)]; e != 0u; e = next[e - 1u]) {
          const float3 pp = vload3(0, photons[e - 1u].p);
          const float dx = pp.x - x.x, dy = pp.y - x.y, dz = pp.z - x.z;
          if (dx * dx + dy * dy + dz * dz > r2) continue;
          const int3 pc = grid_cell(pp, inv_cell);
          if (pc.x != cx || pc.y != cy || pc.z != cz) continue; /* another cell's photon */
          ++m;
          sum += e;
          square_sum += (ulong)e * e;
        }
      }
  counts[i] = m;
  sums[i] = sum;
  square_sums[i] = square_sum;
}
