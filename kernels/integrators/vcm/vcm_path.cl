/* Vertex connection and merging (Georgiev, Krivanek, Davidovic and Slusallek 2012; its
 * report "Implementing Vertex Connection and Merging"): bdpt's subpaths and strategies
 * (kernels/integrators/estimators/bdpt/) with a second technique, merging, weighted against them by
 * the same recursive MIS quantities (kernels/integrators/stages/vertex_mis.cl, StrategyMis).
 *
 * Per pass, over a tile of light_paths pixel indices:
 *   light subpath  as bdpt's, but every non-delta vertex y_k with k <= max_depth is stored
 *                  (merging needs y_max_depth: merged at a camera vertex z_1 it closes a
 *                  path of max_depth bounces) and connects to the camera (t = 1);
 *   camera subpath as bdpt's (emitter hits, next-event estimation, connections to its own
 *                  light subpath), and at each non-delta vertex z_k it merges every stored
 *                  light vertex of the tile within radius r (a hashed grid of cells 2r wide,
 *                  kernels/spatial/hash_grid.cl): y's throughput times z's BSDF for y's
 *                  incoming direction, over eta = pi r^2 light_paths, MIS-weighted by
 *                  vcm_weight_merge. A merge of y_j at z_k is a path of j + k - 1 bounces.
 * As with photons (kernels/integrators/estimators/photon/density.cl) a light vertex merges only where
 * it lies on z's surface (normals within about 37 degrees) and its direction is carried to
 * z's normal first.
 *
 * The modes (VcmMode) switch techniques off: bpt renders bdpt's estimator (StrategyMis's vm =
 * 0: the weights are bdpt's), ppm merges at the first non-delta camera vertex only with weight
 * 1 and sees emitters only through delta paths (SmallVCM's ppm), lt splats light subpaths
 * unweighted and takes the camera's first hit for emitters seen directly, pt keeps dVC = 0 on
 * the camera subpath (an emitter hit's weight then counts NEE alone) and weights NEE with
 * dVCM = dVC = 0 (against the emitter hit alone). */
#ifndef CLPT_INTEGRATORS_VCM_VCM_PATH_CL
#define CLPT_INTEGRATORS_VCM_VCM_PATH_CL

#include "camera/pixel_ray.cl"
#include "integrators/estimators/bdpt/camera_path.cl"
#include "integrators/estimators/bdpt/light_path.cl"
#include "integrators/estimators/photon/density.cl"
#include "shared/vcm_types.h"
#include "spatial/hash_grid.cl"

static inline StrategyMis vcm_mis(__constant const VcmParams* v) {
  StrategyMis m = mis_all_strategies();
  m.vm = v->mis_vm;
  m.vc = v->mis_vc;
  return m;
}

/* Traces the light subpath of one pixel index, stores its vertices in out (at most
 * v->light_vertex_capacity) and splats its camera connections. Returns how many it stored. */
static inline u32 vcm_light_path(__constant const RenderParams* p, __constant const VcmParams* v,
                                 const SceneView* s, const Sampler* sampler,
                                 __global PathVertex* out,
                                 __global float4* splat, u32* rays, u32* connections) {
  const StrategyMis m = vcm_mis(v);
  SubpathState st;
  LightPdfs q;
  PathWalk w;
  if (!bdpt_light_start(p, &m, s, sampler, &st, &q, &w)) return 0u;
  const bool store = vcm_mode_merges(v->mode) || vcm_mode_connects(v->mode);
  const bool connect = v->mode != VCM_MODE_PPM;
  u32 stored = 0u;
  while (w.depth <= p->max_depth && walk_next(s, sampler, &w, rays)) {
    const u32 depth = w.depth;
    bdpt_light_arrive(p, &st, &w, q.finite);
    if (v->mode == VCM_MODE_LT) st.dvcm = st.dvc = 0.0f; /* no strategy but t = 1: weight 1 */
    if (bsdf_has_smooth_lobe(&w.sh)) {
      if (store && stored < v->light_vertex_capacity)
        path_vertex_store(out + stored++, &w.sh, w.wo, &st, depth);
      if (connect) {
        float2 raster = (float2)(0.0f);
        const float3 L = bdpt_camera_connection(p, &m, s, &w.sh, w.wo, &st, depth,
                                                sample_2d(sampler, walk_dim(&w, DIM_LT_LENS)),
                                                &raster, rays, connections);
        if (!is_black(L)) film_splat_at(p, splat, raster, L);
      }
    }
    if (depth >= p->max_depth) break;
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    bdpt_mis_scatter_sample(p, &m, &st, &w.sh, w.wo, &bs);
  }
  return stored;
}

/* Merging at camera vertex sh (oriented to wo, index k, state st): the sum over the tile's
 * light vertices within r of f(wo, y's direction) y.beta, each times its weight (1 in ppm
 * mode), before the camera's throughput and 1 / eta. */
static inline float3 vcm_merge(__constant const RenderParams* p, __constant const VcmParams* v,
                               const StrategyMis* m, const SurfaceHit* sh, float3 wo,
                               const SubpathState* st,
                               u32 k, __global const PathVertex* vertices,
                               __global const u32* starts,
                               __global const GridPoint* points, u32* merges) {
  float3 sum = (float3)(0.0f);
  const float r2 = v->radius * v->radius;
  const float3 x = sh->p;
  const int3 lo = grid_cell(x - (float3)(v->radius), v->inv_cell);
  const int3 hi = grid_cell(x + (float3)(v->radius), v->inv_cell);
  const PhotonShading shading = photon_shading(sh, wo);
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const int3 c = (int3)(cx, cy, cz);
        const u32 b = grid_bucket(c, v->mask);
        for (u32 j = starts[b], end = starts[b + 1u]; j < end; ++j) {
          __global const GridPoint* g = points + j;
          const float3 yp = vload3(0, g->p);
          const float3 d = yp - x;
          if (dot(d, d) > r2) continue;
          const int3 yc = grid_cell(yp, v->inv_cell);
          if (yc.x != cx || yc.y != cy || yc.z != cz) continue; /* another cell's vertex */
          if (g->key + k - 1u > p->max_depth) continue; /* the vertex's depth */
          const float3 n_y = vload3(0, g->n);
          const float c_n = dot(n_y, sh->ng);
          if (fabs(c_n) < PHOTON_NORMAL_COS) continue;
          __global const PathVertex* y = vertices + g->index;
          const float3 wi = rotate_between(n_y, c_n >= 0.0f ? sh->ng : -sh->ng, vload3(0, y->wo));
          const float3 f = bsdf_eval_in_frame(sh, &shading.frame, shading.wo_local, wi,
                                              TRANSPORT_RADIANCE);
          if (is_black(f)) continue;
          ++*merges;
          float weight = 1.0f;
          if (v->mode == VCM_MODE_VCM) {
            const SubpathState ls = path_vertex_state(y);
            weight = vcm_weight_merge(p, m, st, &ls, bsdf_pdf_w(sh, wo, wi), bsdf_pdf_w(sh, wi, wo));
          }
          sum += f * vload3(0, y->beta) * weight;
        }
      }
  return sum;
}

/* The camera subpath of pixel (x, y) with its light subpath lv (count vertices) and the
 * tile's merge grid. With light vertex caching (v->lvc = M > 0, as bdpt's) each camera
 * vertex connects instead to M vertices drawn from the tile's `cached` stored vertices (their
 * slots in `cache`), scaled by cached / (M light_paths). Returns the pixel's estimate;
 * *merged is the part merging added. */
static inline float3 vcm_camera_path(__constant const RenderParams* p,
                                     __constant const VcmParams* v,
                                     const SceneView* s, const Sampler* sampler, u32 x, u32 y,
                                     __global const PathVertex* lv, u32 count,
                                     __global const PathVertex* vertices, __global const u32* cache,
                                     u32 cached, __global const u32* starts,
                                     __global const GridPoint* points,
                                     float3* merged, u32* rays, u32* connections, u32* merges) {
  const StrategyMis m = vcm_mis(v);
  const bool connect = vcm_mode_connects(v->mode);
  const bool vc = connect || v->mode == VCM_MODE_PT; /* next-event estimation */
  const bool merge = vcm_mode_merges(v->mode);
  float3 org, dir;
  pixel_ray(p, sampler, x, y, &org, &dir);
  SubpathState st = bdpt_camera_start(p, dir);
  float3 L = (float3)(0.0f);
  *merged = (float3)(0.0f);
  /* ppm sees emitters only through delta vertices (else merging found that light); on such
   * a path dVCM and dVC are 0, so bdpt's emitter weights are 1 there. */
  bool specular = true;
  PathWalk w = walk_from_camera(p, org, dir, 0u, 0u);
  for (;;) {
    const u32 k = w.depth + 1u;
    if (!walk_next(s, sampler, &w, rays)) {
      if (v->mode != VCM_MODE_PPM || specular) bdpt_gather_escape(p, &m, s, &st, w.beta, w.dir, k, &L);
      break;
    }
    st.beta = w.beta;
    const SurfaceHit* sh = &w.sh;
    const float3 wo = w.wo;
    bdpt_mis_arrive(p, &st, distance(sh->p, w.from), fabs(dot(sh->ng, wo)), 1);
    if (v->mode != VCM_MODE_PPM || specular) bdpt_gather_emitter(p, &m, s, &st, sh, wo, k, &L);
    if (v->mode == VCM_MODE_LT || k > p->max_depth) break;
    if (bsdf_has_smooth_lobe(sh)) {
      specular = false;
      if (vc) {
        /* pt: NEE's weight against the emitter hit alone (no longer light subpaths). */
        SubpathState nee = st;
        if (v->mode == VCM_MODE_PT) nee.dvcm = nee.dvc = 0.0f;
        L += st.beta * bdpt_nee(p, &m, s, sampler, sh, wo, &nee, k, rays, connections);
      }
      if (connect && v->lvc == 0u) {
        for (u32 i = 0u; i < count; ++i)
          L += st.beta * bdpt_connect(p, &m, s, sh, wo, &st, k, lv + i, rays, connections);
      } else if (connect && cached > 0u) {
        float3 sum = (float3)(0.0f);
        for (u32 j = 0u; j < v->lvc; ++j) {
          const float u = sample_1d(sampler, stream_dim(bounce_dim(k - 1u, DIM_LVC_PICK), j));
          const u32 i = min((u32)(u * (float)cached), cached - 1u);
          sum += bdpt_connect(p, &m, s, sh, wo, &st, k, vertices + cache[i], rays, connections);
        }
        L += st.beta * sum * ((float)cached / ((float)v->lvc * (float)v->light_paths));
      }
      if (merge) {
        const float3 M = st.beta * vcm_merge(p, v, &m, sh, wo, &st, k, vertices, starts, points,
                                             merges) * v->vm_normalization;
        L += M;
        *merged += M;
        if (v->mode == VCM_MODE_PPM) break;
      }
    }
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    bdpt_mis_scatter_sample(p, &m, &st, &w.sh, w.wo, &bs);
    if (v->mode == VCM_MODE_PT) st.dvc = 0.0f; /* no strategy with light vertices beyond NEE */
  }
  return L;
}

#endif
