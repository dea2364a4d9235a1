/* The path a primary sample vector stands for in multiplexed MLT (Hachisuka, Kaplanyan and
 * Dachsbacher 2014, "Multiplexed Metropolis Light Transport"): a chain samples paths of one
 * length, `depth` bounces, and the vector chooses, besides both subpaths, which of bdpt's
 * strategies (s light vertices, t camera vertices, s + t = depth + 2) builds the path:
 *   depth 0: s = 0, t = 2 alone (a light seen directly; s = 1, t = 1 is left out, as in bdpt);
 *   else:    s uniform over 0 ... depth + 1 (DIM_MMLT_STRATEGY), t = depth + 2 - s.
 * The contribution is that one strategy's, weighted by bdpt's MIS weight over the strategies of
 * this length (integrators/stages/vertex_mis.cl) and divided by the probability of choosing it:
 *   C = (depth + 2) w_st f_st.
 * Its expectation over the strategy is then the sum of the weighted strategies, bdpt's
 * estimate of the paths of this length; chains of every length together give the image.
 *
 * Both subpaths are traced to their fixed lengths without Russian roulette, each through the
 * functions bdpt's own subpaths use (integrators/estimators/bdpt/), from their streams of the vector
 * (sampler/pss.cl interleaves them): the camera's film position, lens and bounces, the light's
 * emission and bounces. The film position is the camera ray's for t >= 2 and the camera
 * connection's for t = 1 (light tracing). The bdpt MIS weights count one light path per
 * camera path over the film, which is what one chain step is. */
#ifndef CLPT_INTEGRATORS_MLT_MMLT_PATH_CL
#define CLPT_INTEGRATORS_MLT_MMLT_PATH_CL

#include "camera/pixel_ray.cl"
#include "integrators/estimators/bdpt/camera_path.cl"
#include "integrators/estimators/bdpt/light_path.cl"
#include "integrators/mlt/pss_path.cl"

/* The vertex a light subpath ends at: bounce `depth` of the light walk (1: the first hit). */
typedef struct MmltLightVertex {
  SurfaceHit sh; /* oriented to wo */
  float3 wo;     /* towards the light */
  SubpathState st;
} MmltLightVertex;

/* Traces the light subpath to its vertex of bounce `depth` (>= 1). Returns 0 when it ends
 * before (nothing emitted, an escape, no BSDF sample) or ends on a vertex no connection can
 * use (only delta lobes). */
static inline int mmlt_light_vertex(__constant const RenderParams* p, const SceneView* s,
                                    const Sampler* sampler, u32 depth, MmltLightVertex* y,
                                    u32* rays) {
  LightPdfs q;
  PathWalk w;
  const StrategyMis none = mis_all_strategies();
  if (!bdpt_light_start(p, &none, s, sampler, &y->st, &q, &w)) return 0;
  w.roulette = WALK_RR_NONE;
  while (walk_next(s, sampler, &w, rays)) {
    bdpt_light_arrive(p, &y->st, &w, q.finite);
    if (w.depth == depth) {
      if (!bsdf_has_smooth_lobe(&w.sh)) return 0;
      y->sh = w.sh;
      y->wo = w.wo;
      return 1;
    }
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) return 0;
    bdpt_mis_scatter_sample(p, &none, &y->st, &w.sh, w.wo, &bs);
  }
  return 0;
}

/* The strategy's light vertices for a path of `depth` bounces (see the file comment). */
static inline u32 mmlt_light_vertices(const Sampler* sampler, u32 depth) {
  if (depth == 0u) return 0u;
  const u32 n = depth + 2u;
  return min((u32)(sample_1d(sampler, DIM_MMLT_STRATEGY) * (float)n), n - 1u);
}

/* The camera subpath, traced to its vertex t - 1 and closed there by strategy (s, t) with the
 * light vertex y (s >= 2). Returns the weighted contribution f_st w_st; *pixel is the
 * film position's pixel, *raster the film position. */
static inline float3 mmlt_camera_strategy(__constant const RenderParams* p, const SceneView* s,
                                          const Sampler* sampler, u32 s_count, u32 t_count,
                                          const MmltLightVertex* y, u32* pixel, float2* raster,
                                          u32* rays) {
  u32 connections = 0u;
  const StrategyMis none = mis_all_strategies();
  float3 org, dir;
  *pixel = film_sample_ray(p, sampler, &org, &dir, raster);
  SubpathState st = bdpt_camera_start(p, &none, dir);
  PathWalk w = walk_from_camera(p, org, dir, 0u, 0u);
  w.roulette = WALK_RR_NONE;
  const u32 last = t_count - 1u; /* the index of the camera subpath's last vertex */
  float3 L = (float3)(0.0f);
  for (;;) {
    const u32 k = w.depth + 1u;
    if (!walk_next(s, sampler, &w, rays)) {
      if (s_count == 0u && k == last) bdpt_gather_escape(p, &none, s, &st, w.beta, w.dir, k, &L);
      return L;
    }
    st.beta = w.beta;
    bdpt_mis_arrive(p, &st, distance(w.sh.p, w.from), fabs(dot(w.sh.ng, w.wo)), 1);
    if (k == last) {
      if (s_count == 0u) {
        bdpt_gather_emitter(p, &none, s, &st, &w.sh, w.wo, k, &L);
        return L;
      }
      if (!bsdf_has_smooth_lobe(&w.sh)) return (float3)(0.0f);
      if (s_count == 1u) return st.beta * bdpt_nee(p, &none, s, sampler, &w.sh, w.wo, &st, k, rays, &connections);
      return st.beta * bdpt_connect_vertex(p, &none, s, &w.sh, w.wo, &st, k, &y->sh, y->wo,
                                           &y->st, s_count, rays, &connections);
    }
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) return (float3)(0.0f);
    bdpt_mis_scatter_sample(p, &none, &st, &w.sh, w.wo, &bs);
  }
}

/* The path of `depth` bounces the vector stands for, and its target value. */
static inline PssPath mmlt_path(const SceneView* s, __constant const RenderParams* p,
                                const Sampler* sampler, u32 depth, u32* rays) {
  PssPath path;
  path.L = (float3)(0.0f);
  path.target = 0.0f;
  path.pixel = 0u;
  path.raster = (float2)(0.0f);
  const u32 n = depth == 0u ? 1u : depth + 2u;
  const u32 s_count = mmlt_light_vertices(sampler, depth);
  const u32 t_count = depth + 2u - s_count;
  MmltLightVertex y;
  if (s_count >= 2u && !mmlt_light_vertex(p, s, sampler, s_count - 1u, &y, rays)) return path;
  if (t_count == 1u) {
    u32 connections = 0u;
    const StrategyMis none = mis_all_strategies();
    path.L = bdpt_camera_connection(p, &none, s, &y.sh, y.wo, &y.st, s_count - 1u,
                                    bdpt_light_sample_2d(sampler, bounce_dim(s_count - 1u,
                                    DIM_LT_LENS)),
                                    0, &path.raster, rays, &connections);
    path.pixel = film_pixel_of(p, path.raster);
  } else {
    path.L = mmlt_camera_strategy(p, s, sampler, s_count, t_count, &y, &path.pixel, &path.raster, rays);
  }
  path.L *= (float)n;
  const float v = luminance(path.L);
  path.target = is_finite3(path.L) && v > 0.0f ? v : 0.0f;
  return path;
}

#endif
