/* BDPT's camera subpath: traced like pt's path (kernels/integrators/estimators/path_trace.cl) from a
 * pixel, and at each camera vertex z_k (k = 1 for the first hit, so t = k + 1 camera vertices
 * counting the camera itself) it gathers the strategies that end there:
 *   s = 0   the subpath hits an emitter (or escapes to the environment),
 *   s = 1   next-event estimation: a fresh light sample,
 *   s >= 2  a connection to light vertex y_(s-1) of the light subpath with the same key,
 * each for paths of at most max_depth bounces (s + t - 2 <= max_depth), weighted by
 * kernels/integrators/stages/vertex_mis.cl. Each strategy is a function of its own
 * (bdpt_gather_escape, bdpt_gather_emitter, bdpt_nee, bdpt_connect_vertex), which multiplexed
 * MLT calls one at a time (kernels/integrators/mlt/mmlt_path.cl). */
#ifndef CLPT_INTEGRATORS_BDPT_CAMERA_PATH_CL
#define CLPT_INTEGRATORS_BDPT_CAMERA_PATH_CL

#include "camera/camera_importance.cl"
#include "camera/pixel_ray.cl"
#include "integrators/stages/path_vertex.cl"
#include "integrators/stages/shading_correction.cl"
#include "integrators/stages/vertex_mis.cl"
#include "integrators/stages/walk.cl"
#include "light/light.cl"

/* s = 1 at camera vertex sh (oriented to wo), k = its index. */
static inline float3 bdpt_nee(__constant const RenderParams* p, const StrategyMis* m,
                              const SceneView* s,
                              const Sampler* sampler, const SurfaceHit* sh, float3 wo,
                              const SubpathState* st, u32 k, u32* rays, u32* connections) {
  if (s->num_lights == 0u) return (float3)(0.0f);
  if (bdpt_strategy_weight(m, 1u, k + 1u, 1.0f) == 0.0f) return (float3)(0.0f);
  const LightSample ls = light_illuminate(s, sh->p, sample_1d(sampler, bounce_dim(k - 1u, DIM_LIGHT_SELECT)),
                                          sample_2d(sampler, bounce_dim(k - 1u, DIM_LIGHT_POINT)));
  if (!(ls.pdf_w > 0.0f) || is_black(ls.Le)) return (float3)(0.0f);
  const float3 f = bsdf_eval_cos(sh, wo, ls.wi, TRANSPORT_RADIANCE);
  if (is_black(f)) return (float3)(0.0f);
  const LightPdfs q = light_pdfs_sample(s, &ls);
  const float direct_w = q.finite ? q.direct * ls.dist * ls.dist / q.cos_light : q.direct;
  const float w = bdpt_weight_nee(p, m, st, ls.pdf_w, ls.is_delta, direct_w, q.emit_w, q.cos_light,
                                  bsdf_pdf_w(sh, wo, ls.wi), bsdf_pdf_w(sh, ls.wi, wo),
                                  fabs(dot(sh->ng, ls.wi)));
  ++*rays;
  ++*connections;
  const float3 org = offset_ray_origin_towards(sh->p, sh->ng, ls.wi);
  if (light_sample_occluded(s, org, &ls)) return (float3)(0.0f);
  return f * ls.Le * (bdpt_strategy_weight(m, 1u, k + 1u, w) / ls.pdf_w);
}

/* s >= 2: camera vertex sh (oriented to wo, index k) joined to light vertex y (oriented to
 * y_wo, subpath state ls) of a light subpath with s_count vertices up to it. */
static inline float3 bdpt_connect_vertex(__constant const RenderParams* p, const StrategyMis* m,
                                         const SceneView* s, const SurfaceHit* sh, float3 wo,
                                         const SubpathState* st, u32 k, const SurfaceHit* y,
                                         float3 y_wo,
                                         const SubpathState* ls, u32 s_count, u32* rays,
                                         u32* connections) {
  if (s_count + k - 1u > p->max_depth) return (float3)(0.0f);
  if (bdpt_strategy_weight(m, s_count, k + 1u, 1.0f) == 0.0f) return (float3)(0.0f);
  const float3 d = y->p - sh->p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return (float3)(0.0f);
  const float dist = sqrt(dist2);
  const float3 dir = d / dist; /* camera vertex -> light vertex */
  const float3 f_cam = bsdf_eval_cos(sh, wo, dir, TRANSPORT_RADIANCE);
  if (is_black(f_cam)) return (float3)(0.0f);
  const float3 f_light =
      bsdf_eval_cos(y, y_wo, -dir, TRANSPORT_IMPORTANCE) * shading_correction(y, y_wo, -dir);
  if (is_black(f_light)) return (float3)(0.0f);
  const float cos_cam = fabs(dot(sh->ng, dir)), cos_light = fabs(dot(y->ng, dir));
  const float w = bdpt_weight_connect(p, m, st, ls, bsdf_pdf_w(sh, wo, dir) * cos_light / dist2,
                                      bsdf_pdf_w(sh, dir, wo),
                                      bsdf_pdf_w(y, y_wo, -dir) * cos_cam / dist2,
                                      bsdf_pdf_w(y, -dir, y_wo));
  ++*rays;
  ++*connections;
  const float3 org = offset_ray_origin_towards(sh->p, sh->ng, dir);
  if (segment_occluded(s, org, offset_ray_origin_towards(y->p, y->ng, -dir))) return (float3)(0.0f);
  return f_cam * f_light * ls->beta * volume_transmittance(s, sh, dir, dist) *
         (bdpt_strategy_weight(m, s_count, k + 1u, w) / dist2);
}

/* s >= 2 with a stored light vertex v. */
static inline float3 bdpt_connect(__constant const RenderParams* p, const StrategyMis* m,
                                  const SceneView* s,
                                  const SurfaceHit* sh, float3 wo, const SubpathState* st, u32 k,
                                  __global const PathVertex* v, u32* rays, u32* connections) {
  const u32 s_count = v->depth + 1u;
  if (s_count + k - 1u > p->max_depth) return (float3)(0.0f);
  if (bdpt_strategy_weight(m, s_count, k + 1u, 1.0f) == 0.0f) return (float3)(0.0f);
  const SurfaceHit y = path_vertex_surface(v);
  const SubpathState ls = path_vertex_state(v);
  return bdpt_connect_vertex(p, m, s, sh, wo, st, k, &y, vload3(0, v->wo), &ls, s_count, rays,
                             connections);
}

/* The camera subpath's state at the camera, for a ray in direction dir, weighted against m's
 * light_per_pixel light subpaths per pixel (stages/vertex_mis.cl). */
static inline SubpathState bdpt_camera_start(__constant const RenderParams* p, const StrategyMis* m,
                                             float3 dir) {
  SubpathState st;
  st.beta = (float3)(1.0f);
  st.dvcm = bdpt_mis(p, m->light_per_pixel / camera_ray_pdf_w(&p->camera, dir));
  st.dvc = 0.0f;
  st.dvm = 0.0f;
  return st;
}

/* s = 0 through the environment: the camera subpath (state st, throughput beta) escaped in
 * direction dir from its vertex k - 1; seen directly (k = 1) it has no other strategy. Adds
 * the weighted radiance to *L (one expression with the sum, so that the compiler's
 * contraction into a fused multiply-add stays what it was when this was inline code). */
static inline void bdpt_gather_escape(__constant const RenderParams* p, const StrategyMis* m,
                                      const SceneView* s, const SubpathState* st, float3 beta, float3 dir, u32 k,
                                      float3* L) {
  if (!env_present(s)) return;
  const LightPdfs q = light_pdfs_env(s, dir);
  const float w_env = k == 1u ? 1.0f : bdpt_weight_hit_light(p, st, q.direct, q.emit_w);
  *L += beta * env_radiance(s, dir) * bdpt_strategy_weight(m, 0u, k + 1u, w_env);
}

/* s = 0 at an emitter: camera vertex k (sh, oriented to wo, state st after arriving). Seen
 * directly (k = 1) it has weight 1 (s = 1, t = 1 is left out). Adds to *L as above. */
static inline void bdpt_gather_emitter(__constant const RenderParams* p, const StrategyMis* m,
                                       const SceneView* s, const SubpathState* st, const SurfaceHit* sh, float3 wo,
                                       u32 k,
                                       float3* L) {
  const float3 Le = light_radiance(s, sh, wo);
  if (is_black(Le)) return;
  float w_hit = 1.0f;
  if (k > 1u) {
    const LightPdfs q = light_pdfs_area(s, sh->triangle, fabs(dot(sh->ng, wo)));
    w_hit = bdpt_weight_hit_light(p, st, q.direct, q.emit_w);
  }
  *L += st->beta * Le * bdpt_strategy_weight(m, 0u, k + 1u, w_hit);
}

/* The camera subpath of one pixel sample joined with light subpath `lv` (`count` vertices);
 * returns the pixel's estimate from every strategy with t >= 2.
 *
 * Light vertex caching (b->lvc = M > 0; Davidovic et al. 2014): `lv` is instead the
 * cache of all `count` vertices the tile's `paths` light subpaths stored, and each camera
 * vertex connects to M of them chosen uniformly, each contribution scaled by
 * count / (M paths). Its expectation is that of connecting to all vertices of one light
 * subpath (the mean over subpaths of their sum), so the estimate stays unbiased with the
 * same MIS weights; they are optimal for M near the mean number of vertices per subpath. */
static inline float3 bdpt_camera_path(__constant const RenderParams* p,
                                      __constant const BdptParams* b, const SceneView* s,
                                      const Sampler* sampler, u32 x, u32 y,
                                      __global const PathVertex* lv, u32 count, u32 paths,
                                      u32* rays,
                                      u32* connections) {
  float3 org, dir;
  pixel_ray(p, sampler, x, y, &org, &dir);
  const StrategyMis mis = mis_bdpt(b);
  SubpathState st = bdpt_camera_start(p, &mis, dir);
  float3 L = (float3)(0.0f);
  PathWalk w = walk_from_camera(p, org, dir, 0u, 0u);
  for (;;) {
    const u32 k = w.depth + 1u; /* the vertex's index on the camera subpath */
    if (!walk_next(s, sampler, &w, rays)) {
      bdpt_gather_escape(p, &mis, s, &st, w.beta, w.dir, k, &L);
      break;
    }
    st.beta = w.beta;
    const SurfaceHit* sh = &w.sh;
    const float3 wo = w.wo;
    bdpt_mis_arrive(p, &st, distance(sh->p, w.from), fabs(dot(sh->ng, wo)), 1); /* vertex to vertex */
    bdpt_gather_emitter(p, &mis, s, &st, sh, wo, k, &L);
    if (k > p->max_depth) break;
    if (bsdf_has_smooth_lobe(sh)) {
      L += st.beta * bdpt_nee(p, &mis, s, sampler, sh, wo, &st, k, rays, connections);
      if (b->lvc == 0u) {
        for (u32 i = 0u; i < count; ++i)
          L += st.beta * bdpt_connect(p, &mis, s, sh, wo, &st, k, lv + i, rays, connections);
      } else if (count > 0u) {
        float3 cached = (float3)(0.0f);
        for (u32 j = 0u; j < b->lvc; ++j) {
          const float u = sample_1d(sampler, stream_dim(bounce_dim(k - 1u, DIM_LVC_PICK), j));
          const u32 i = min((u32)(u * (float)count), count - 1u);
          cached += bdpt_connect(p, &mis, s, sh, wo, &st, k, lv + i, rays, connections);
        }
        L += st.beta * cached * ((float)count / ((float)b->lvc * (float)paths));
      }
    }
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    bdpt_mis_scatter_sample(p, &mis, &st, &w.sh, w.wo, &bs);
  }
  return L;
}

#endif
