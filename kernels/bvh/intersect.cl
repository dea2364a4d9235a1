/* Ray queries against the scene BVH: closest hit and any hit (shadow rays).
 *
 * Traversal: the 4-wide BVH (BvhNode4, host/bvh/bvh.h's collapse_bvh4). A node's four child
 * boxes are tested at once (float4 lanes), the children the ray enters are visited nearest
 * first (closest hit) through a private stack of CLPT_BVH4_STACK entries, a leaf's
 * triangles when its entry comes up; any hit tests a node's leaf children right away.
 *
 * Box test: slabs with a precomputed reciprocal direction, where 1/0 = +-inf is allowed
 * (the build never uses -cl-fast-relaxed-math). The entry and exit planes of each axis are
 * chosen by the direction's sign, so for an axis-parallel ray the entry distance is -inf
 * and the exit +inf when the origin is inside the slab, and both +inf (or both -inf) when it
 * is outside. The one NaN case, 0 * inf for an origin exactly in a face plane, is dropped
 * by the order of the min/max comparisons, which counts the ray as inside that slab:
 * conservative, so triangles lying in the face plane are still tested. The exit distance is
 * widened by 1 + 2 gamma(3) (Ize 2013, "Robust BVH Ray Traversal"; pbrt-v4) so rounding
 * never culls a box the ray touches. An empty slot's box (bmin = +inf, bmax = -inf; an empty
 * scene's root has only those) is never entered, except by a ray with a NaN origin, which
 * enters every box: its count of 0 leaves it nothing to read.
 *
 * Triangle test: the watertight test of Woop, Benthin and Wald, "Watertight Ray/Triangle
 * Intersection", JCGT 2(1), 2013, two-sided, accepting t in (0, tmax). Rays through a
 * shared edge or vertex of a closed mesh never slip through: each edge function is
 * evaluated from the same sheared vertex values by both triangles that share it, with
 * floating-point contraction off so the two evaluations are exact negatives. (The paper's
 * double-precision fallback for edge functions that are exactly zero is omitted: OpenCL
 * 1.2 devices need not support double; zeros are accepted, so a ray exactly through an
 * edge hits both triangles rather than neither.)
 *
 * Alpha: a candidate hit on a MASK or BLEND material may be a hole (material/alpha.cl); the
 * material's flags are read only for candidates that pass the triangle test. */
#ifndef CLPT_BVH_INTERSECT_CL
#define CLPT_BVH_INTERSECT_CL

#include "core/hit.cl"
#include "core/prefetch.cl"
#include "core/scene_view.cl"
#include "material/alpha.cl"
#include "shared/bvh_constants.h"

/* The traversal functions are large and called from several places; inlining them into
 * each kernel lets the compiler keep the per-ray constants in registers. static, as every
 * function of the kernels: a C99 `inline` definition alone is no external definition, and a
 * call the compiler leaves out of line then has nothing to link to (clang's NVPTX and AMDGPU
 * targets leave such calls unresolved; docs/ARCHITECTURE.md, portability rules).
 * CLPT_NO_ALWAYS_INLINE (scripts/oclgrind-check.sh) leaves inlining to the compiler: Oclgrind
 * 21.10 cannot run the noalias scope declarations that forced inlining of a function
 * returning a struct leaves behind, even at -cl-opt-disable. */
#if defined(__clang__) && !defined(CLPT_NO_ALWAYS_INLINE)
#define CLPT_INLINE static inline __attribute__((always_inline))
#else
#define CLPT_INLINE static inline
#endif

/* Per-ray constants of the watertight test: the axis kz where the direction is largest, the
 * other two axes (kx, ky) and the shear that maps the direction to (0, 0, 1). */
typedef struct TriangleRay {
  float ox, oy, oz; /* origin permuted to (kx, ky, kz) */
  float sx, sy, sz;
  int kx, ky, kz;
} TriangleRay;

CLPT_INLINE TriangleRay triangle_ray(float3 org, float3 dir) {
  const float3 a = fabs(dir);
  const int kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  const float d[3] = {dir.x, dir.y, dir.z};
  const float o[3] = {org.x, org.y, org.z};
  if (d[kz] < 0.0f) { /* keep the winding (only the sign of det depends on it) */
    const int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  TriangleRay r;
  r.kx = kx;
  r.ky = ky;
  r.kz = kz;
  r.sx = d[kx] / d[kz];
  r.sy = d[ky] / d[kz];
  r.sz = 1.0f / d[kz];
  r.ox = o[kx];
  r.oy = o[ky];
  r.oz = o[kz];
  return r;
}

/* The watertight test's arithmetic, written once for its two forms: intersect_triangle on
 * floats and intersect_triangle4 on float4 lanes (TYPE). Each form loads its vertices and
 * decides where to stop; the operations and their order are these, which is what keeps the
 * two forms' hits bit for bit the same.
 *
 * CLPT_TRIANGLE_EDGES declares the vertices relative to the origin, sheared so the ray runs
 * along +z from (0, 0, 0) (az, bz, cz, ax, ay, bx, by, cx, cy), and the scaled barycentrics,
 * the edge functions u, v, w of the 2D triangle at the origin. P0X .. P2Z: the three vertices'
 * components in (kx, ky, kz) order; r: the TriangleRay. */
#define CLPT_TRIANGLE_EDGES(TYPE, r, P0X, P0Y, P0Z, P1X, P1Y, P1Z, P2X, P2Y, P2Z)           \
  const TYPE az = (P0Z) - (r)->oz, bz = (P1Z) - (r)->oz, cz = (P2Z) - (r)->oz;               \
  const TYPE ax = ((P0X) - (r)->ox) - (r)->sx * az, ay = ((P0Y) - (r)->oy) - (r)->sy * az;   \
  const TYPE bx = ((P1X) - (r)->ox) - (r)->sx * bz, by = ((P1Y) - (r)->oy) - (r)->sy * bz;   \
  const TYPE cx = ((P2X) - (r)->ox) - (r)->sx * cz, cy = ((P2Y) - (r)->oy) - (r)->sy * cz;   \
  const TYPE u = cx * by - cy * bx;                                                         \
  const TYPE v = ax * cy - ay * cx;                                                         \
  const TYPE w = bx * ay - by * ax

/* CLPT_TRIANGLE_T_ERROR declares delta_t, for rejecting t that rounding alone could have
 * made positive: a conservative bound on the error of the computed t from the errors of the
 * sheared coordinates and edge functions (the derivation of Pharr, Jakob and Humphreys, PBR
 * 3rd ed., section 3.9.6). Offsetting the origin is not enough by itself: t's error grows with
 * the vertices' distance from the origin, so a ray leaving a large triangle (a 2 km ground
 * plane) could re-hit it or a coplanar neighbour just above t = 0. It reads the names
 * CLPT_TRIANGLE_EDGES declares, and tz0 .. tz2 (sz times az .. cz) and inv_det (1 / (u + v +
 * w)). gamma(n) = n eps / (1 - n eps), eps = 2^-24. */
#define CLPT_GAMMA(n) (((float)(n) * 0x1.0p-24f) / (1.0f - (float)(n) * 0x1.0p-24f))
#define CLPT_TRIANGLE_T_ERROR(TYPE)                                                           \
  const TYPE max_zt = fmax(fabs(tz0), fmax(fabs(tz1), fabs(tz2)));                           \
  const TYPE max_xt = fmax(fabs(ax), fmax(fabs(bx), fabs(cx)));                              \
  const TYPE max_yt = fmax(fabs(ay), fmax(fabs(by), fabs(cy)));                              \
  const TYPE delta_z = CLPT_GAMMA(3) * max_zt;                                               \
  const TYPE delta_x = CLPT_GAMMA(5) * (max_xt + max_zt);                                    \
  const TYPE delta_y = CLPT_GAMMA(5) * (max_yt + max_zt);                                    \
  const TYPE delta_e =                                                                       \
      2.0f * (CLPT_GAMMA(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);        \
  const TYPE max_e = fmax(fabs(u), fmax(fabs(v), fabs(w)));                                  \
  const TYPE delta_t =                                                                       \
      3.0f * (CLPT_GAMMA(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * fabs(inv_det)

/* Intersects leaf-order triangle `tri`; on a hit with t in (0, tmax) stores t and the
 * barycentrics of v[1], v[2]. A ray with a zero or NaN direction hits nothing. */
CLPT_INLINE bool intersect_triangle(const SceneView* s, const TriangleRay* r, u32 tri, float tmax,
                               float* t_out, float* b1_out, float* b2_out) {
#pragma OPENCL FP_CONTRACT OFF
  const Triangle T = s->triangles[tri];
  __global const float* p0 = s->vertices[T.v[0]].p;
  __global const float* p1 = s->vertices[T.v[1]].p;
  __global const float* p2 = s->vertices[T.v[2]].p;
  const int kx = r->kx, ky = r->ky, kz = r->kz;
  CLPT_TRIANGLE_EDGES(float, r, p0[kx], p0[ky], p0[kz], p1[kx], p1[ky], p1[kz], p2[kx], p2[ky],
                      p2[kz]);
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const float det = u + v + w;
  if (det == 0.0f) return false; /* degenerate, or the ray lies in the triangle's plane */

  const float tz0 = r->sz * az, tz1 = r->sz * bz, tz2 = r->sz * cz;
  const float tt = u * tz0 + v * tz1 + w * tz2;
  const float inv_det = 1.0f / det;
  const float t = tt * inv_det;
  if (!(t > 0.0f && t < tmax)) return false; /* also rejects NaN */
  {
    CLPT_TRIANGLE_T_ERROR(float);
    if (t <= delta_t) return false;
  }
  *t_out = t;
  *b1_out = v * inv_det;
  *b2_out = w * inv_det;
  return true;
}

/* How a leaf's triangles are tested: CLPT_TRIANGLE_LANES 4, four at a time in float4 lanes
 * (intersect_triangle4), which the host asks for on CPU devices (cl::device_kind_options): on
 * PoCL a lane is one SSE instruction, where the triangle-at-a-time loop ran the arithmetic once
 * per triangle (Cornell box: 1.35x the incoherent rays per second, pt 0.85x the time;
 * docs/BENCHMARKS.md). 1 (the default): one at a time, for GPUs, where a work-item's float4 is
 * four registers and four instructions: Intel's dg2 compiler spilled 85 in pt_render with the
 * lanes against 53 without. Both give bit-identical hits (tests/bvh_test.cpp runs both). */
#ifndef CLPT_TRIANGLE_LANES
#define CLPT_TRIANGLE_LANES 1
#endif

/* intersect_triangle for the leaf-order triangles tri .. tri + n - 1 (n in 1..4, one group of
 * a leaf) at once, one per float4 lane: the same operations in the same order, so each lane's
 * t, b1 and b2 are bit for bit what intersect_triangle computes. The positions come from the
 * group's nine rows in s->tri_lanes (host/bvh/bvh.h's triangle_lanes: row 3 v + a, axis a of
 * vertex v, at 9 tri + row * n), read in the ray's axis order (kx, ky, kz) straight into the
 * lanes: no vertex index and no gather. Lanes past n read the next group's floats and are
 * masked out. Returns -1 in the lanes that hit with t in (0, tmax), 0 elsewhere. */
#if CLPT_TRIANGLE_LANES == 4
CLPT_INLINE int4 intersect_triangle4(const SceneView* s, const TriangleRay* r, u32 tri, u32 n,
                                     float tmax, float4* t_out, float4* b1_out, float4* b2_out) {
#pragma OPENCL FP_CONTRACT OFF
  __global const float* g = s->tri_lanes + 9u * tri;
  const u32 ox = (u32)r->kx * n, oy = (u32)r->ky * n, oz = (u32)r->kz * n;
  const float4 p0x = vload4(0, g + ox), p0y = vload4(0, g + oy), p0z = vload4(0, g + oz);
  g += 3u * n;
  const float4 p1x = vload4(0, g + ox), p1y = vload4(0, g + oy), p1z = vload4(0, g + oz);
  g += 3u * n;
  const float4 p2x = vload4(0, g + ox), p2y = vload4(0, g + oy), p2z = vload4(0, g + oz);

  CLPT_TRIANGLE_EDGES(float4, r, p0x, p0y, p0z, p1x, p1y, p1z, p2x, p2y, p2z);
  int4 ok = (int4)(0, 1, 2, 3) < (int4)((int)n);
  ok &= ~(((u < 0.0f) | (v < 0.0f) | (w < 0.0f)) & ((u > 0.0f) | (v > 0.0f) | (w > 0.0f)));
  const float4 det = u + v + w;
  ok &= det != 0.0f;

  const float4 tz0 = r->sz * az, tz1 = r->sz * bz, tz2 = r->sz * cz;
  const float4 tt = u * tz0 + v * tz1 + w * tz2;
  const float4 inv_det = 1.0f / det;
  const float4 t = tt * inv_det;
  ok &= (t > 0.0f) & (t < tmax);
  if (!any(ok)) return ok;
  {
    CLPT_TRIANGLE_T_ERROR(float4);
    ok &= ~(t <= delta_t);
  }
  *t_out = t;
  *b1_out = v * inv_det;
  *b2_out = w * inv_det;
  return ok;
}
#endif

/* The boxes of a wide node's four children against the ray: each lane's entry distance where
 * the ray enters that child's box at some t in [0, tmax], else +inf. The near and far plane
 * of each axis are picked by the direction's sign (neg_x etc.: 1 where it is negative);
 * written as (a > b ? a : b) with the running value second, so a NaN lane (0 * inf, an
 * origin exactly in a face plane) is dropped, which counts the ray as inside that slab:
 * conservative. The exit distance is widened by 1 + 2 gamma(3) (Ize 2013; pbrt-v4) so
 * rounding never culls a box the ray touches; an empty slot (bmin +inf, bmax -inf) is never
 * entered. */
CLPT_INLINE float4 box4_entry(__global const BvhNode4* node, float3 org, float3 inv, int neg_x,
                              int neg_y, int neg_z, float tmax) {
  const float4 lo_x = vload4(0, node->bmin_x), hi_x = vload4(0, node->bmax_x);
  const float4 lo_y = vload4(0, node->bmin_y), hi_y = vload4(0, node->bmax_y);
  const float4 lo_z = vload4(0, node->bmin_z), hi_z = vload4(0, node->bmax_z);
  const float4 in_x = ((neg_x ? hi_x : lo_x) - org.x) * inv.x;
  const float4 out_x = ((neg_x ? lo_x : hi_x) - org.x) * inv.x;
  const float4 in_y = ((neg_y ? hi_y : lo_y) - org.y) * inv.y;
  const float4 out_y = ((neg_y ? lo_y : hi_y) - org.y) * inv.y;
  const float4 in_z = ((neg_z ? hi_z : lo_z) - org.z) * inv.z;
  const float4 out_z = ((neg_z ? lo_z : hi_z) - org.z) * inv.z;
  float4 t0 = (float4)(0.0f), t1 = (float4)(tmax);
  t0 = in_x > t0 ? in_x : t0;
  t0 = in_y > t0 ? in_y : t0;
  t0 = in_z > t0 ? in_z : t0;
  t1 = out_x < t1 ? out_x : t1;
  t1 = out_y < t1 ? out_y : t1;
  t1 = out_z < t1 ? out_z : t1;
  return t0 <= t1 * 1.00000036f ? t0 : (float4)(INFINITY); /* 1 + 2 gamma(3) */
}

/* A traversal stack entry: a wide node's index, or (BVH4_LEAF set) one leaf slot of a node,
 * node << 2 | slot, whose triangles are child[slot]'s range; BVH4_NONE: no entry. */
#define BVH4_LEAF 0x80000000u
#define BVH4_NONE 0xffffffffu

/* Sorts (t, e) pairs by t, a compare-exchange of two named variables (no array: it stays in
 * registers on every device). */
#define BVH4_ORDER(ta, ea, tb, eb)      \
  do {                                  \
    if (tb < ta) {                      \
      const float t_ = ta;              \
      const u32 e_ = ea;                \
      ta = tb;                          \
      ea = eb;                          \
      tb = t_;                          \
      eb = e_;                          \
    }                                   \
  } while (0)

/* The entries of a node's children the ray enters (entry distance < INFINITY), nearest
 * first: the nearest is returned (BVH4_NONE when none) and the others are pushed, farthest
 * first, so that they are popped near to far. Sorted by a five-exchange network. */
CLPT_INLINE u32 bvh4_children(__global const BvhNode4* node, u32 index, float4 t, u32* stack,
                              int* sp) {
  const int4 c = vload4(0, node->child);
  float t0 = t.x, t1 = t.y, t2 = t.z, t3 = t.w;
  u32 e0 = c.x >= 0 ? (u32)c.x : BVH4_LEAF | index << 2;
  u32 e1 = c.y >= 0 ? (u32)c.y : BVH4_LEAF | index << 2 | 1u;
  u32 e2 = c.z >= 0 ? (u32)c.z : BVH4_LEAF | index << 2 | 2u;
  u32 e3 = c.w >= 0 ? (u32)c.w : BVH4_LEAF | index << 2 | 3u;
  BVH4_ORDER(t0, e0, t1, e1);
  BVH4_ORDER(t2, e2, t3, e3);
  BVH4_ORDER(t0, e0, t2, e2);
  BVH4_ORDER(t1, e1, t3, e3);
  BVH4_ORDER(t1, e1, t2, e2);
  if (t3 < INFINITY) stack[(*sp)++] = e3;
  if (t2 < INFINITY) stack[(*sp)++] = e2;
  if (t1 < INFINITY) stack[(*sp)++] = e1;
  return t0 < INFINITY ? e0 : BVH4_NONE;
}

/* The closest hit with t in (0, tmax). Fills *hit and returns true, or returns false and
 * leaves *hit as it was. */
CLPT_INLINE bool intersect_closest(const SceneView* s, float3 org, float3 dir, float tmax, Hit* hit) {
  __global const BvhNode4* nodes = s->nodes;
  const TriangleRay tr = triangle_ray(org, dir);
  const float3 inv = 1.0f / dir;
  const int neg_x = signbit(dir.x), neg_y = signbit(dir.y), neg_z = signbit(dir.z);

  float best_t = tmax, best_b1 = 0.0f, best_b2 = 0.0f;
  u32 best_tri = 0xffffffffu;
  u32 stack[CLPT_BVH4_STACK];
  int sp = 0;
  u32 entry = 0; /* the root */
  for (;;) {
    if (entry & BVH4_LEAF) {
      __global const BvhNode4* node = nodes + ((entry & ~BVH4_LEAF) >> 2);
      const u32 slot = entry & 3u;
      const u32 first = (u32)~node->child[slot], end = first + node->count[slot];
#if CLPT_TRIANGLE_LANES == 4
      for (u32 i = first; i < end; i += 4u) {
        float4 t, b1, b2;
        const int4 hit = intersect_triangle4(s, &tr, i, min(end - i, 4u), best_t, &t, &b1, &b2);
        if (!any(hit)) continue;
        /* In leaf order, as one triangle at a time would: a later lane replaces the best hit
         * only when strictly nearer (ties keep the first). The lanes read no triangle row, so
         * the shading of the hit would wait for one after the traversal: a candidate's row is
         * fetched while the traversal goes on (1 M-triangle spheres: pt 1.034x the paths/s). */
#define CLPT_TRI4_ACCEPT(l, c)                                                                  \
  if (hit.c && t.c < best_t && !alpha_hole(s, i + (l), b1.c, b2.c, org, dir)) {                \
    best_t = t.c;                                                                               \
    best_b1 = b1.c;                                                                             \
    best_b2 = b2.c;                                                                             \
    best_tri = i + (l);                                                                         \
    CLPT_PREFETCH(s->triangles + best_tri);                                                     \
  }
        CLPT_TRI4_ACCEPT(0u, x)
        CLPT_TRI4_ACCEPT(1u, y)
        CLPT_TRI4_ACCEPT(2u, z)
        CLPT_TRI4_ACCEPT(3u, w)
#undef CLPT_TRI4_ACCEPT
      }
#else
      for (u32 i = first; i < end; ++i) {
        float t, b1, b2;
        if (intersect_triangle(s, &tr, i, best_t, &t, &b1, &b2) && !alpha_hole(s, i, b1, b2, org, dir)) {
          best_t = t;
          best_b1 = b1;
          best_b2 = b2;
          best_tri = i;
        }
      }
#endif
      entry = BVH4_NONE;
    } else {
      __global const BvhNode4* node = nodes + entry;
      entry = bvh4_children(node, entry, box4_entry(node, org, inv, neg_x, neg_y, neg_z, best_t), stack, &sp);
    }
    if (entry == BVH4_NONE) {
      if (sp == 0) break;
      entry = stack[--sp];
    }
  }
  if (best_tri == 0xffffffffu) return false;
  hit->t = best_t;
  hit->b1 = best_b1;
  hit->b2 = best_b2;
  hit->triangle = best_tri;
  return true;
}

/* Whether anything is hit with t in (0, tmax); stops at the first hit found. A node's leaf
 * children are tested as soon as the node is, its inner ones pushed in any order. */
CLPT_INLINE bool intersect_any(const SceneView* s, float3 org, float3 dir, float tmax) {
  __global const BvhNode4* nodes = s->nodes;
  const TriangleRay tr = triangle_ray(org, dir);
  const float3 inv = 1.0f / dir;
  const int neg_x = signbit(dir.x), neg_y = signbit(dir.y), neg_z = signbit(dir.z);

  u32 stack[CLPT_BVH4_STACK];
  int sp = 0;
  u32 index = 0; /* the root */
  for (;;) {
    __global const BvhNode4* node = nodes + index;
    const float4 t = box4_entry(node, org, inv, neg_x, neg_y, neg_z, tmax);
    for (int k = 0; k < 4; ++k) {
      const float tk = k == 0 ? t.x : k == 1 ? t.y : k == 2 ? t.z : t.w;
      if (!(tk < INFINITY)) continue;
      const int c = node->child[k];
      if (c >= 0) {
        stack[sp++] = (u32)c;
        continue;
      }
      const u32 first = (u32)~c, end = first + node->count[k];
#if CLPT_TRIANGLE_LANES == 4
      for (u32 i = first; i < end; i += 4u) {
        float4 th, b1, b2;
        const int4 hit = intersect_triangle4(s, &tr, i, min(end - i, 4u), tmax, &th, &b1, &b2);
        if (!any(hit)) continue;
        if ((hit.x && !alpha_hole(s, i, b1.x, b2.x, org, dir)) ||
            (hit.y && !alpha_hole(s, i + 1u, b1.y, b2.y, org, dir)) ||
            (hit.z && !alpha_hole(s, i + 2u, b1.z, b2.z, org, dir)) ||
            (hit.w && !alpha_hole(s, i + 3u, b1.w, b2.w, org, dir)))
          return true;
      }
#else
      for (u32 i = first; i < end; ++i) {
        float th, b1, b2;
        if (intersect_triangle(s, &tr, i, tmax, &th, &b1, &b2) && !alpha_hole(s, i, b1, b2, org, dir))
          return true;
      }
#endif
    }
    if (sp == 0) break;
    index = stack[--sp];
  }
  return false;
}

/* A shadow ray: whether anything is hit with t in (0, tmax) is the question; tmax 0: none
 * to trace (nothing can block it). Made before the shading it waits for, so that a GPU keeps
 * these seven values live across that shading instead of the inputs they come from. */
typedef struct ShadowRay {
  float3 org, dir;
  float tmax;
} ShadowRay;

/* The shadow ray of the segment from org to target. Both ends must already be off the
 * surfaces they lie on (offset_ray_origin in core/ray.cl, towards each other): the segment is
 * shortened only by a relative 1e-4 for rounding, and that alone does not keep a short
 * segment from ending inside the target's own surface, since each end's offset is a fixed
 * number of ulps (issue 14: a light 5 cm from a surface facing it shadowed itself). */
CLPT_INLINE ShadowRay segment_ray(float3 org, float3 target) {
  ShadowRay r;
  r.org = org;
  const float3 d = target - org;
  const float len = length(d);
  if (!(len > 0.0f) || !isfinite(len)) {
    r.dir = (float3)(0.0f, 0.0f, 1.0f);
    r.tmax = 0.0f;
    return r;
  }
  r.dir = d / len;
  r.tmax = len * (1.0f - 1e-4f);
  return r;
}

CLPT_INLINE bool shadow_ray_occluded(const SceneView* s, const ShadowRay* r) {
  return r->tmax > 0.0f && intersect_any(s, r->org, r->dir, r->tmax);
}

/* Whether anything blocks the segment from org to target (segment_ray). */
CLPT_INLINE bool segment_occluded(const SceneView* s, float3 org, float3 target) {
  const ShadowRay r = segment_ray(org, target);
  return shadow_ray_occluded(s, &r);
}

#endif
