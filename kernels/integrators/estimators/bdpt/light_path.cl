/* BDPT's light subpath (Veach 1997 ch. 10; Georgiev 2012): traced from a light like the
 * light tracer's paths (kernels/integrators/lt/light_trace.cl), with the MIS state of
 * kernels/integrators/stages/vertex_mis.cl. Each surface vertex y_k with a non-delta BSDF
 *   - connects to the camera (strategy s = k + 1, t = 1) and splats its weighted share, and
 *   - is stored for the camera kernel's connections when k < max_depth (the strategies
 *     s = k + 1, t >= 2 need at most max_depth bounces: s + t - 2 <= max_depth).
 * The light's own vertex y_0 is not stored: strategies with s = 1 sample a fresh light point
 * (next-event estimation), as in SmallVCM.
 *
 * The sampler: the same key (pixel index, sample index) as the camera subpath it will be
 * joined with, in its own stream of dimensions (DIM_BDPT_LIGHT_STREAM), laid out like a light
 * tracer's path. Its start (bdpt_light_start), the MIS update at a vertex (bdpt_light_arrive)
 * and the camera connection (bdpt_camera_connection) are what multiplexed MLT's light
 * subpaths are made of too (kernels/integrators/mlt/mmlt_path.cl). */
#ifndef CLPT_INTEGRATORS_BDPT_LIGHT_PATH_CL
#define CLPT_INTEGRATORS_BDPT_LIGHT_PATH_CL

#include "camera/camera_importance.cl"
#include "film/splat_filter.cl"
#include "integrators/stages/path_vertex.cl"
#include "integrators/stages/vertex_mis.cl"
#include "integrators/stages/walk.cl"
#include "light/light.cl"

static inline float bdpt_light_sample_1d(const Sampler* sampler, u32 dim) {
  return sample_1d(sampler, stream_dim(dim, DIM_BDPT_LIGHT_STREAM));
}
static inline float2 bdpt_light_sample_2d(const Sampler* sampler, u32 dim) {
  return sample_2d(sampler, stream_dim(dim, DIM_BDPT_LIGHT_STREAM));
}

/* t = 1, light vertex sh (oriented to wo, towards the light) seen through lens point u_lens:
 * the camera's side of the connection, its f |cos| (with the shading correction) and the two
 * densities its MIS weight needs: camera_pdf_a, with which a camera ray would find the vertex
 * (per unit area and per light path: pdf_camera_film cos / d^2), and rev, the vertex's density
 * of scattering back along the light subpath given the camera side. */
typedef struct CameraLink {
  CameraConnection c;
  float3 f;
  float camera_pdf_a;
  float rev;
} CameraLink;

/* Fills *l; 0 when the camera cannot see the vertex or its BSDF sends nothing there. */
static inline int bdpt_camera_link(__constant const RenderParams* p, const SurfaceHit* sh, float3 wo,
                                   float2 u_lens, CameraLink* l) {
  l->c = camera_connect(&p->camera, p->width, p->height, sh->p, u_lens);
  if (!l->c.valid) return 0;
  l->f = bsdf_eval_cos(sh, wo, l->c.wi, TRANSPORT_IMPORTANCE) * shading_correction(sh, wo, l->c.wi);
  if (is_black(l->f)) return 0;
  l->camera_pdf_a = l->c.pdf_w * fabs(dot(sh->ng, l->c.wi)) / (l->c.dist * l->c.dist);
  l->rev = bsdf_pdf_w(sh, l->c.wi, wo);
  return 1;
}

/* The link's shadow ray and, unoccluded, its contribution to the film with MIS weight w (the
 * subpath's throughput beta) and its film position in *raster. */
static inline float3 bdpt_camera_link_trace(const SceneView* s, const SurfaceHit* sh,
                                            const CameraLink* l, float3 beta, float w,
                                            float2* raster, u32* rays, u32* connections) {
  ++*rays;
  ++*connections;
  const float3 org = offset_ray_origin_towards(sh->p, sh->ng, l->c.wi);
  if (intersect_any(s, org, l->c.wi, l->c.dist * (1.0f - 1e-4f))) return (float3)(0.0f);
  *raster = l->c.raster;
  return beta * l->f * (l->c.weight * w);
}

/* t = 1: light vertex sh (oriented to wo, towards the light, at bounce `depth`) connected
 * to the camera through lens point u_lens. Returns its weighted contribution to the film and
 * sets *raster to its film position; 0 when the strategy is off, the camera cannot see the vertex
 * or the shadow ray is blocked. splat: the film the caller adds the result to, whose pixel is
 * fetched while the shadow ray is traced (film_splat_prefetch); 0: none. */
static inline float3 bdpt_camera_connection(__constant const RenderParams* p, const StrategyMis* m,
                                            const SceneView* s, const SurfaceHit* sh, float3 wo,
                                            const SubpathState* st, u32 depth, float2 u_lens,
                                            __global float4* splat, float2* raster,
                                            u32* rays, u32* connections) {
  const float strategy = bdpt_strategy_weight(m, depth + 1u, 1u, 1.0f);
  if (strategy == 0.0f) return (float3)(0.0f);
  CameraLink l;
  if (!bdpt_camera_link(p, sh, wo, u_lens, &l)) return (float3)(0.0f);
  if (splat) film_splat_prefetch(p, splat, l.c.raster);
  const float w =
      bdpt_strategy_weight(m, depth + 1u, 1u, bdpt_weight_camera(p, m, st, l.camera_pdf_a, l.rev));
  return bdpt_camera_link_trace(s, sh, &l, st->beta, w, raster, rays, connections);
}

/* bdpt's t = 1 strategy: the connection above, splatted. */
static inline void bdpt_connect_camera(__constant const RenderParams* p, const StrategyMis* m,
                                       const SceneView* s, const SurfaceHit* sh, float3 wo, const SubpathState* st,
                                       u32 depth, float2 u_lens, __global float4* splat, u32* rays,
                                       u32* connections) {
  float2 raster = (float2)(0.0f);
  const float3 L =
      bdpt_camera_connection(p, m, s, sh, wo, st, depth, u_lens, splat, &raster, rays, connections);
  if (!is_black(L)) film_splat_at(p, splat, raster, L);
}

/* The start of a light subpath: a light, a point on it and a direction from the light stream's
 * dimensions, the subpath state at the light (vertex_mis.cl) in *st, the emission's densities
 * in *q. Returns 0 when nothing is emitted. */
static inline int bdpt_light_start(__constant const RenderParams* p, const StrategyMis* m,
                                   const SceneView* s, const Sampler* sampler, SubpathState* st,
                                   LightPdfs* q, PathWalk* w) {
  if (s->num_lights == 0u) return 0;
  const LightEmission e = light_emit(s, bdpt_light_sample_1d(sampler, bounce_dim(0u, DIM_LIGHT_SELECT)),
                                     bdpt_light_sample_2d(sampler, DIM_LT_EMIT_POS),
                                     bdpt_light_sample_2d(sampler, DIM_LT_EMIT_DIR));
  if (!(e.pdf_a > 0.0f && e.pdf_w > 0.0f && e.pdf_select > 0.0f) || is_black(e.Le)) return 0;
  *q = light_pdfs_emission(s, &e);
  st->beta = e.Le * (e.cos_light / q->emit_w);
  st->dvcm = bdpt_mis(p, q->direct / q->emit_w);
  st->dvc = (e.is_delta_pos || e.is_delta_dir) ? 0.0f : bdpt_mis(p, q->cos_light / q->emit_w);
  st->dvm = st->dvc * m->vc;
  *w = walk_from_light(e.p, light_emission_origin(s, &e), e.dir, st->beta, DIM_BDPT_LIGHT_STREAM,
                       WALK_RR_PATH);
  return 1;
}

/* The MIS update on arriving at the walk's vertex. Distances between the vertices, not the
 * ray's t from its offset origin: the connection weights measure edges between vertices too
 * (tests/bdpt_mis_test.cpp). `finite`: the light of the subpath is not at infinity (whose
 * first segment has no distance). */
static inline void bdpt_light_arrive(__constant const RenderParams* p, SubpathState* st,
                                     const PathWalk* w, int finite) {
  st->beta = w->beta;
  bdpt_mis_arrive(p, st, distance(w->sh.p, w->from), fabs(dot(w->sh.ng, w->wo)),
                  w->depth > 1u || finite);
}

/* Traces one light subpath and stores its connectable vertices: in `out` (capacity
 * b->light_vertex_capacity), or with light vertex caching (b->lvc > 0) appended to the
 * tile's shared cache `pool` through the counter *pool_count. Returns how many it stored.
 * *rays counts every ray traced, *connections the shadow rays of strategies (here: t = 1). */
static inline u32 bdpt_light_path(__constant const RenderParams* p, __constant const BdptParams* b,
                                  const SceneView* s,
                                  const Sampler* sampler, __global PathVertex* out,
                                  __global PathVertex* pool, volatile __global u32* pool_count,
                                  __global float4* splat, u32* rays, u32* connections) {
  SubpathState st;
  LightPdfs q;
  PathWalk w;
  const StrategyMis mis = mis_bdpt(b);
  if (!bdpt_light_start(p, &mis, s, sampler, &st, &q, &w)) return 0u;
  u32 stored = 0u;
  while (w.depth <= p->max_depth && walk_next(s, sampler, &w, rays)) {
    const u32 depth = w.depth;
    bdpt_light_arrive(p, &st, &w, q.finite);
    if (bsdf_has_smooth_lobe(&w.sh)) {
      if (depth < p->max_depth && stored < b->light_vertex_capacity) {
        ++stored;
        if (b->lvc) path_vertex_store(pool + atomic_inc(pool_count), &w.sh, w.wo, &st, depth);
        else path_vertex_store(out + stored - 1u, &w.sh, w.wo, &st, depth);
      }
      bdpt_connect_camera(p, &mis, s, &w.sh, w.wo, &st, depth,
                          sample_2d(sampler, walk_dim(&w, DIM_LT_LENS)), splat, rays, connections);
    }
    if (depth >= p->max_depth) break;
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    bdpt_mis_scatter_sample(p, &mis, &st, &w.sh, w.wo, &bs);
  }
  return stored;
}

#endif
