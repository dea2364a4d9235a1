/* Vertex connection and merging (Georgiev, Krivanek, Davidovic and Slusallek 2012; its
 * report "Implementing Vertex Connection and Merging"): bdpt's subpaths and strategies
 * (kernels/integrators/estimators/bdpt/) with a second technique, merging, weighted against them by
 * the same recursive MIS quantities (kernels/integrators/stages/vertex_mis.cl, StrategyMis).
 *
 * Per pass, over a tile of pixel indices:
 *   light subpaths light_per_pixel per pixel index (--vcm-light-paths, 1 by default), each
 *                  as bdpt's, but every non-delta vertex y_k with k <= max_depth is stored
 *                  (merging needs y_max_depth: merged at a camera vertex z_1 it closes a
 *                  path of max_depth bounces) and connects to the camera (t = 1);
 *   camera subpath as bdpt's (emitter hits, next-event estimation, connections to its own
 *                  light subpath), and at its first non-delta vertex z_k (merge_first,
 *                  --vcm-merge first; at every one with --vcm-merge all) it merges every
 *                  stored light vertex of the tile within radius r (a hashed grid of cells
 *                  2r wide, kernels/spatial/hash_grid.cl): y's throughput times z's BSDF for y's
 *                  incoming direction, over eta = pi r^2 light_paths (every light subpath
 *                  of the tile), MIS-weighted by
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

/* The strategies' factors with merging factors vm, vc against the pass's light subpaths. */
static inline StrategyMis vcm_strategies(__constant const VcmParams* v, float vm, float vc) {
  StrategyMis m = mis_merging(vm, vc, (int)v->merge_first);
  m.light_per_pixel = (float)v->light_per_pixel;
  return m;
}

static inline StrategyMis vcm_mis(__constant const VcmParams* v) {
  return vcm_strategies(v, v->mis_vm, v->mis_vc);
}

/* The pass's factors the light subpaths are traced with (with merge_first no merging term). */
static inline StrategyMis vcm_light_mis(__constant const VcmParams* v) {
  const StrategyMis pass = vcm_mis(v);
  return mis_light_side(&pass);
}

/* How a camera path merges: its radius, 1 / eta (a merge's kernel over the light paths) and
 * the MIS factors of its eta. One for the pass, or with per-pixel radii its pixel's. */
typedef struct MergeSetting {
  float radius;
  float normalization;
  StrategyMis mis;
} MergeSetting;

static inline MergeSetting vcm_merge_setting(__constant const RenderParams* p,
                                             __constant const VcmParams* v, float radius) {
  MergeSetting g;
  g.mis = vcm_mis(v);
  g.radius = v->radius;
  g.normalization = v->vm_normalization;
  if (!v->pixel_radius) return g;
  const float eta = v->eta_per_r2 * radius * radius;
  g.radius = radius;
  g.normalization = 1.0f / eta;
  g.mis = vcm_strategies(v, vcm_mode_merges(v->mode) ? bdpt_mis(p, eta) : 0.0f,
                         vcm_mode_connects(v->mode) ? bdpt_mis(p, 1.0f / eta) : 0.0f);
  return g;
}

/* A light subpath's state st (slopes e) as a camera path merging with setting g weights it:
 * traced with the pass's factors, moved to g's when the pixels have radii of their own. */
static inline SubpathState vcm_rebase(__constant const VcmParams* v, const MergeSetting* g,
                                      SubpathState st, EtaSlopes e) {
  if (!v->pixel_radius) return st;
  const StrategyMis traced = vcm_light_mis(v);
  return eta_rebase(st, e, &traced, &g->mis);
}

/* The same for stored light vertex y, its slopes beside it (written with per-pixel radii only,
 * so read only then). */
static inline SubpathState vcm_light_state(__constant const VcmParams* v, const MergeSetting* g,
                                           __global const PathVertex* y,
                                           __global const float2* slopes) {
  EtaSlopes e;
  e.dvc_vm = e.dvm_vc = 0.0f;
  if (v->pixel_radius) {
    e.dvc_vm = slopes->x;
    e.dvm_vc = slopes->y;
  }
  return vcm_rebase(v, g, path_vertex_state(y), e);
}

/* A pixel's (r, N) after a pass whose first merging vertex found m light vertices: sppm's
 * shrink (N' = N + alpha m, r'^2 = r^2 N' / (N + m)), which leaves a pixel that finds
 * nothing at its radius. */
static inline float2 vcm_radius_update(__constant const VcmParams* v, float2 rn, u32 m) {
  if (m == 0u) return rn;
  const float n = rn.y + v->alpha * (float)m;
  return (float2)(rn.x * sqrt(n / (rn.y + (float)m)), n);
}

/* Traces one light subpath of a pixel index, stores its vertices in out (at most
 * v->light_vertex_capacity) and splats its camera connections, each one of the pass's
 * light_per_pixel light subpaths of the pixel. Returns how many it stored. */
static inline u32 vcm_light_path(__constant const RenderParams* p, __constant const VcmParams* v,
                                 const SceneView* s, const Sampler* sampler,
                                 __global PathVertex* out, __global float2* out_slopes,
                                 __global const float2* pixel_radii,
                                 __global float4* splat, u32* rays, u32* connections) {
  const StrategyMis m = vcm_light_mis(v);
  SubpathState st;
  LightPdfs q;
  PathWalk w;
  if (!bdpt_light_start(p, &m, s, sampler, &st, &q, &w)) return 0u;
  EtaSlopes e = eta_slopes_start(&st);
  const bool store = vcm_mode_merges(v->mode) || vcm_mode_connects(v->mode);
  const bool connect = v->mode != VCM_MODE_PPM;
  u32 stored = 0u;
  while (w.depth <= p->max_depth && walk_next(s, sampler, &w, rays)) {
    const u32 depth = w.depth;
    bdpt_light_arrive(p, &st, &w, q.finite);
    if (v->pixel_radius) eta_slopes_arrive(p, &e, fabs(dot(w.sh.ng, w.wo)));
    if (v->mode == VCM_MODE_LT) st.dvcm = st.dvc = 0.0f; /* no strategy but t = 1: weight 1 */
    if (bsdf_has_smooth_lobe(&w.sh)) {
      if (store && stored < v->light_vertex_capacity) {
        if (v->pixel_radius) out_slopes[stored] = (float2)(e.dvc_vm, e.dvm_vc);
        path_vertex_store(out + stored++, &w.sh, w.wo, &st, depth);
      }
      CameraLink l;
      if (connect && bdpt_camera_link(p, &w.sh, w.wo, sample_2d(sampler, walk_dim(&w, DIM_LT_LENS)),
                                      &l)) {
        film_splat_prefetch(p, splat, l.c.raster);
        /* t = 1, weighted against the techniques of the pixel it lands in: with per-pixel
         * radii that pixel's eta (a box filter: the film position's pixel receives it). */
        const MergeSetting g = vcm_merge_setting(
            p, v, v->pixel_radius ? pixel_radii[film_pixel_of(p, l.c.raster)].x : v->radius);
        const SubpathState at = vcm_rebase(v, &g, st, e);
        float2 raster = (float2)(0.0f);
        const float3 L = bdpt_camera_link_trace(
            s, &w.sh, &l, st.beta,
            bdpt_weight_camera(p, &g.mis, &at, l.camera_pdf_a, l.rev) / g.mis.light_per_pixel,
            &raster, rays, connections);
        if (!is_black(L)) film_splat_at(p, splat, raster, L);
      }
    }
    if (depth >= p->max_depth) break;
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    /* bdpt_mis_scatter_sample's update, its reverse density shared with the slopes'. */
    const float rev = bs.is_delta ? bs.pdf_w : bsdf_pdf_w(&w.sh, bs.wi, w.wo);
    const float cos_out = fabs(dot(w.sh.ng, bs.wi));
    if (v->pixel_radius) eta_slopes_scatter(p, &m, &e, st.dvcm, bs.pdf_w, rev, cos_out, bs.is_delta);
    bdpt_mis_scatter(p, &m, &st, bs.pdf_w, rev, cos_out, bs.is_delta);
  }
  return stored;
}

/* Merging at camera vertex sh (oriented to wo, index k, state st) with setting g: the sum
 * over the tile's light vertices within g's radius of f(wo, y's direction) y.beta, each times
 * its weight (1 in ppm mode), before the camera's throughput and 1 / eta. *merges counts them. */
static inline float3 vcm_merge(__constant const RenderParams* p, __constant const VcmParams* v,
                               const MergeSetting* g, const SurfaceHit* sh, float3 wo,
                               const SubpathState* st,
                               u32 k, __global const PathVertex* vertices,
                               __global const float2* slopes, __global const u32* starts,
                               __global const GridPoint* points, u32* merges) {
  float3 sum = (float3)(0.0f);
  const float r2 = g->radius * g->radius;
  const float3 x = sh->p;
  const int3 lo = grid_cell(x - (float3)(g->radius), v->inv_cell);
  const int3 hi = grid_cell(x + (float3)(g->radius), v->inv_cell);
  const PhotonShading shading = photon_shading(sh, wo);
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const int3 c = (int3)(cx, cy, cz);
        const u32 b = grid_bucket(c, v->mask);
        for (u32 j = starts[b], end = starts[b + 1u]; j < end; ++j) {
          __global const GridPoint* gp = points + j;
          const float3 yp = vload3(0, gp->p);
          const float3 d = yp - x;
          if (dot(d, d) > r2) continue;
          const int3 yc = grid_cell(yp, v->inv_cell);
          if (yc.x != cx || yc.y != cy || yc.z != cz) continue; /* another cell's vertex */
          if (gp->key + k - 1u > p->max_depth) continue; /* the vertex's depth */
          const float3 n_y = vload3(0, gp->n);
          const float c_n = dot(n_y, sh->ng);
          if (fabs(c_n) < PHOTON_NORMAL_COS) continue;
          __global const PathVertex* y = vertices + gp->index;
          const float3 wi = rotate_between(n_y, c_n >= 0.0f ? sh->ng : -sh->ng, vload3(0, y->wo));
          const float3 f = bsdf_eval_in_frame(sh, &shading.frame, shading.wo_local, wi,
                                              TRANSPORT_RADIANCE);
          if (is_black(f)) continue;
          ++*merges;
          float weight = 1.0f;
          if (v->mode == VCM_MODE_VCM) {
            const SubpathState ls = vcm_light_state(v, g, y, slopes + gp->index);
            weight = vcm_weight_merge(p, &g->mis, st, &ls, bsdf_pdf_w(sh, wo, wi),
                                      bsdf_pdf_w(sh, wi, wo));
          }
          sum += f * vload3(0, y->beta) * weight;
        }
      }
  return sum;
}

/* s >= 2 with stored light vertex y (its slopes beside it), weighted with factors mk (g's at
 * this camera vertex): bdpt_connect with the light vertex's state moved to g's factors. The
 * pass rule calls bdpt_connect itself: one path through bdpt_connect_vertex for both grew
 * vcm_camera's NVIDIA stack from 400 to 720 bytes (scripts/kernel_compile_check.py --targets
 * nvptx --programs vcm). */
static inline float3 vcm_connect(__constant const RenderParams* p, __constant const VcmParams* v,
                                 const MergeSetting* g, const StrategyMis* mk,
                                 const SceneView* s, const SurfaceHit* sh,
                                 float3 wo, const SubpathState* st, u32 k,
                                 __global const PathVertex* y, __global const float2* slopes,
                                 u32* rays, u32* connections) {
  if (!v->pixel_radius) return bdpt_connect(p, mk, s, sh, wo, st, k, y, rays, connections);
  const u32 s_count = y->depth + 1u;
  if (s_count + k - 1u > p->max_depth) return (float3)(0.0f);
  const SurfaceHit ys = path_vertex_surface(y);
  const SubpathState ls = vcm_light_state(v, g, y, slopes);
  return bdpt_connect_vertex(p, mk, s, sh, wo, st, k, &ys, vload3(0, y->wo), &ls, s_count,
                             rays, connections);
}

/* The camera subpath of pixel (x, y) with its light subpath lv (count vertices) and the
 * tile's merge grid, merging with setting g. With light vertex caching (v->lvc = M > 0, as
 * bdpt's) each camera vertex connects instead to M vertices drawn from the tile's `cached`
 * stored vertices (their slots in `cache`), scaled by cached / (M light_paths). Returns the
 * pixel's estimate; *merged is the part merging added, *found the merges of its first merging
 * vertex. slopes, lv_slopes: the EtaSlopes of vertices and lv, slot for slot (read with
 * per-pixel radii). */
static inline float3 vcm_camera_path(__constant const RenderParams* p,
                                     __constant const VcmParams* v, const MergeSetting* g,
                                     const SceneView* s, const Sampler* sampler, u32 x, u32 y,
                                     __global const PathVertex* lv,
                                     __global const float2* lv_slopes, u32 count,
                                     __global const PathVertex* vertices,
                                     __global const float2* slopes, __global const u32* cache,
                                     u32 cached, __global const u32* starts,
                                     __global const GridPoint* points,
                                     float3* merged, u32* found, u32* rays, u32* connections,
                                     u32* merges) {
  const StrategyMis m = g->mis;
  const bool connect = vcm_mode_connects(v->mode);
  const bool vc = connect || v->mode == VCM_MODE_PT; /* next-event estimation */
  const bool merge = vcm_mode_merges(v->mode);
  float3 org, dir;
  pixel_ray(p, sampler, x, y, &org, &dir);
  SubpathState st = bdpt_camera_start(p, &m, dir);
  float3 L = (float3)(0.0f);
  *merged = (float3)(0.0f);
  *found = 0u;
  bool first_merge = true;
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
    /* The factors at this vertex: with merge_first merging terms at the first non-delta one
     * alone (stages/vertex_mis.cl). */
    const bool smooth = bsdf_has_smooth_lobe(sh);
    const bool first = smooth && specular;
    const StrategyMis mk = mis_at_camera_vertex(&m, first);
    if (smooth) {
      specular = false;
      if (vc) {
        /* pt: NEE's weight against the emitter hit alone (no longer light subpaths). */
        SubpathState nee = st;
        if (v->mode == VCM_MODE_PT) nee.dvcm = nee.dvc = 0.0f;
        L += st.beta * bdpt_nee(p, &mk, s, sampler, sh, wo, &nee, k, rays, connections);
      }
      if (connect && v->lvc == 0u) {
        for (u32 i = 0u; i < count; ++i)
          L += st.beta * vcm_connect(p, v, g, &mk, s, sh, wo, &st, k, lv + i, lv_slopes + i,
                                     rays, connections);
      } else if (connect && cached > 0u) {
        float3 sum = (float3)(0.0f);
        for (u32 j = 0u; j < v->lvc; ++j) {
          const float u = sample_1d(sampler, stream_dim(bounce_dim(k - 1u, DIM_LVC_PICK), j));
          const u32 i = min((u32)(u * (float)cached), cached - 1u);
          sum += vcm_connect(p, v, g, &mk, s, sh, wo, &st, k, vertices + cache[i],
                             slopes + cache[i], rays, connections);
        }
        L += st.beta * sum * ((float)cached / ((float)v->lvc * (float)v->light_paths));
      }
      if (merge && (first || !v->merge_first)) {
        const u32 before = *merges;
        const float3 M = st.beta * vcm_merge(p, v, g, sh, wo, &st, k, vertices, slopes, starts,
                                             points, merges) * g->normalization;
        if (first_merge) *found = *merges - before;
        first_merge = false;
        L += M;
        *merged += M;
        if (v->mode == VCM_MODE_PPM) break;
      }
    }
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    bdpt_mis_scatter_sample(p, &mk, &st, &w.sh, w.wo, &bs);
    if (v->mode == VCM_MODE_PT) st.dvc = 0.0f; /* no strategy with light vertices beyond NEE */
  }
  return L;
}

#endif
