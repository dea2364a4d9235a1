/* A hashed uniform grid over points, rebuilt every pass: sppm's photons (Hachisuka and
 * Jensen 2009 hash visible points; clpt hashes the pass's photons and lets each pixel gather,
 * so no pixel statistic needs an atomic) and vcm's light vertices. Cells are cubes of side
 * 1 / inv_cell; cell (i, j, k) lives in bucket hash(i, j, k) & mask (Teschner et al. 2003's
 * primes), and each bucket is a linked list threaded through the points: heads[bucket] and
 * next[point] hold a point index + 1, 0 ending the list. Insertion is one atomic exchange
 * per point. Buckets are shared by cells that collide, so a query skips points whose own
 * cell is not the one it asked for (each point is then met once). */
#ifndef CLPT_PHOTON_HASH_GRID_CL
#define CLPT_PHOTON_HASH_GRID_CL

#include "shared/photon_types.h"

/* floor(p * inv_cell), saturated to the int range. */
static inline int3 grid_cell(float3 p,
                             float inv_cell) { return convert_int3_sat_rtn(p * inv_cell); }

static inline u32 grid_bucket(int3 c, u32 mask) {
  return (((u32)c.x * 73856093u) ^ ((u32)c.y * 19349663u) ^ ((u32)c.z * 83492791u)) & mask;
}

/* Point i at position p joins its cell's bucket list. */
static inline void grid_insert_point(float3 p, u32 i, float inv_cell, u32 mask,
                                     volatile __global u32* heads, __global u32* next) {
  next[i] = atomic_xchg(&heads[grid_bucket(grid_cell(p, inv_cell), mask)], i + 1u);
}

/* The cell-sorted form (vcm's light vertices): the points of bucket b are points[starts[b]]
 * .. points[starts[b + 1] - 1], each with its position, so that a query reads a bucket's
 * candidates side by side instead of following a list through the points' own records
 * (192-byte PathVertexes over tens of MB for vcm; docs/BENCHMARKS.md, session 31). Built by a
 * counting sort: grid_count_point counts each point into its bucket (starts zeroed before),
 * the host turns the counts into bucket starts (an exclusive sum, with the total at
 * starts[buckets]) and copies them into cursor, and grid_fill_point places each point. */
static inline void grid_count_point(float3 p, float inv_cell, u32 mask, volatile __global u32* counts) {
  atomic_inc(&counts[grid_bucket(grid_cell(p, inv_cell), mask)]);
}

static inline void grid_fill_point(float3 p, float3 n, u32 key, u32 i, float inv_cell, u32 mask,
                                   volatile __global u32* cursor, __global GridPoint* points) {
  __global GridPoint* g = points + atomic_inc(&cursor[grid_bucket(grid_cell(p, inv_cell), mask)]);
  vstore3(p, 0, g->p);
  g->index = i;
  vstore3(n, 0, g->n);
  g->key = key;
}

static inline void grid_insert(__global const Photon* photons, u32 i, float inv_cell, u32 mask,
                               volatile __global u32* heads, __global u32* next) {
  grid_insert_point(vload3(0, photons[i].p), i, inv_cell, mask, heads, next);
}

#endif
