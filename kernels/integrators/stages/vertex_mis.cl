/* Bidirectional MIS weights in O(1) per strategy, after Georgiev, "Implementing Vertex
 * Connection and Merging" (2012): the connection strategies of bdpt, and with vertex merging
 * (vcm, kernels/integrators/vcm.cl) the merging ones too. Without merging (bdpt, mmlt) the
 * StrategyMis merging factors are 0 and the weights are bdpt's.
 *
 * A path x0 ... xk can be sampled by k + 2 strategies (s light vertices, t camera vertices,
 * s + t = k + 1). The balance or power heuristic weight of one of them is 1 / sum_i (p_i/p_s)^b,
 * and the ratios p_i / p_s telescope: each subpath carries, at its last vertex, two partial
 * sums (dVCM, dVC) from which a strategy's weight needs only the densities at the connection.
 * The quantities (per subpath, updated as it is traced):
 *   start (light):   dVCM = direct / emit_w, dVC = cos_light / emit_w (0 for delta lights),
 *                    dVM = dVC * vc
 *   start (camera):  dVCM = N_light / pdf_camera_pixel = 1 / pdf_camera_film, dVC = dVM = 0
 *   each hit, distance d, cosine cos_in at the hit:  dVCM *= d^2 (not after an infinite light's
 *                    first segment), then dVCM, dVC, dVM /= cos_in
 *   each non-delta scattering with pdfs fwd (sampled) and rev (the reverse direction),
 *                    cos_out at the vertex:
 *                    dVC = cos_out / fwd * (dVC * rev + dVCM + vm),
 *                    dVM = cos_out / fwd * (dVM * rev + dVCM * vc + 1), dVCM = 1 / fwd
 *                    (vm and the 1: merging at the vertex left; 0 where no merge is made
 *                    there, below)
 *   each delta scattering: dVCM = 0, dVC *= cos_out, dVM *= cos_out
 * all raised to the heuristic's power. vm = eta and vc = 1 / eta (raised likewise) are
 * StrategyMis' factors, eta = pi r^2 N_merge the ratio of a merge's density to a connection's
 * at the same vertex (N_merge light paths merged with each camera path, radius r); vm is 0
 * without merging, vc 0 without connections. Densities convert between solid angle and area with
 * geometric-normal cosines; Russian roulette stays out of the weights (a partition of unity
 * over strategies is all the estimator needs, as in pbrt-v3's BDPT).
 *
 * Where merges are made. Georgiev's VCM merges at every non-delta vertex of the camera subpath.
 * With merge_first (vcm's --vcm-merge first) a path has one merging technique at most: at its
 * first vertex from the camera with a non-delta lobe, where photon mapping gathers. A
 * connection's or merge's camera vertex is non-delta, so that vertex lies on the camera
 * subpath for every strategy but light tracing (t = 1), where it is the light vertex seen by
 * the camera. The weights then keep the merge terms of that vertex alone: a light subpath is
 * traced with no merge term at all (vm = 0 and dVM's 1 left out), light tracing's weight
 * keeps vm (the merge at the vertex it connects), a connection's weight drops vm on its light
 * side, and on the camera subpath vm and the 1 are kept at the first non-delta
 * vertex only (mis_at_camera_vertex).
 *
 * N_light, the light paths per sample index, is width * height times StrategyMis'
 * light_per_pixel (1 but for vcm's --vcm-light-paths): each sample index traces that many
 * light paths per pixel, so the light tracing strategy (t = 1) takes N_light samples per
 * pixel against one for the camera strategies; a camera subpath starts with dVCM =
 * light_per_pixel / pdf_camera_film, and light tracing's camera density per light path is
 * pdf_camera_film cos / d^2 / light_per_pixel. The strategy s = 1, t = 1 (a light point seen
 * by the camera) is left out, as in SmallVCM: a light seen directly (s = 0, t = 2) has weight 1. */
#ifndef CLPT_INTEGRATORS_BDPT_MIS_CL
#define CLPT_INTEGRATORS_BDPT_MIS_CL

#include "bsdf/bsdf.cl"
#include "integrators/stages/path_vertex.cl"
#include "shared/render_types.h"

static inline float bdpt_mis(__constant const RenderParams* p, float x) {
  return p->mis == MIS_BALANCE ? x : x * x;
}

/* How a bidirectional estimator weights its strategies: the merging factors of the header,
 * vm = mis(eta) and vc = mis(1 / eta), both 0 for bdpt and mmlt; and which strategies count
 * (bdpt's --bdpt-strategy: only (only_s, only_t), with or without its weight; every strategy
 * when only_s is BDPT_ALL_STRATEGIES). */
typedef struct StrategyMis {
  float vm;       /* merging at this vertex (the camera vertex; for t = 1 the light vertex) */
  float vm_one;   /* dVM's 1 in the scattering update: 1 where merging is made at the vertex */
  float vc;
  u32 only_s;
  u32 only_t;
  int unweighted;
  int merge_first; /* merging at the first non-delta camera vertex only */
  float light_per_pixel; /* light subpaths per pixel and sample index (N_light / pixels) */
} StrategyMis;

/* Every strategy, MIS-weighted, no merging (mmlt; bdpt without --bdpt-strategy). */
static inline StrategyMis mis_all_strategies(void) {
  StrategyMis m;
  m.vm = 0.0f;
  m.vm_one = 1.0f;
  m.vc = 0.0f;
  m.only_s = BDPT_ALL_STRATEGIES;
  m.only_t = 0u;
  m.unweighted = 0;
  m.merge_first = 0;
  m.light_per_pixel = 1.0f;
  return m;
}

/* Merging at every non-delta vertex (Georgiev 2012) with factors vm and vc, or with
 * merge_first at the first non-delta camera vertex only. */
static inline StrategyMis mis_merging(float vm, float vc, int merge_first) {
  StrategyMis m = mis_all_strategies();
  m.vm = vm;
  m.vc = vc;
  m.merge_first = merge_first;
  return m;
}

/* The factors a light subpath is traced with: m's, but with merge_first no merging term. */
static inline StrategyMis mis_light_side(const StrategyMis* m) {
  StrategyMis l = *m;
  if (m->merge_first) l.vm = l.vm_one = 0.0f;
  return l;
}

/* The factors at a camera vertex (its scattering, next-event estimation, connections): m's,
 * but with merge_first merging terms only at the first non-delta vertex (`first`). */
static inline StrategyMis mis_at_camera_vertex(const StrategyMis* m, int first) {
  StrategyMis c = *m;
  if (m->merge_first && !first) c.vm = c.vm_one = 0.0f;
  return c;
}

/* bdpt's: no merging, the strategies --bdpt-strategy selects. */
static inline StrategyMis mis_bdpt(__constant const BdptParams* b) {
  StrategyMis m = mis_all_strategies();
  m.only_s = b->strategy_s;
  m.only_t = b->strategy_t;
  m.unweighted = b->unweighted != 0u;
  return m;
}

/* Arrival at a hit at distance dist under cosine cos_in (geometric); `scale_by_distance` is 0
 * only for the first segment of a light path from an infinite light. */
static inline void bdpt_mis_arrive(__constant const RenderParams* p, SubpathState* st, float dist,
                                   float cos_in, int scale_by_distance) {
  if (scale_by_distance) st->dvcm *= bdpt_mis(p, dist * dist);
  const float c = bdpt_mis(p, cos_in);
  st->dvcm /= c;
  st->dvc /= c;
  st->dvm /= c;
}

/* Scattering into a direction of density fwd (rev: the reverse direction's density), leaving
 * under cosine cos_out (geometric); delta: the direction came from a Dirac lobe. */
static inline void bdpt_mis_scatter(__constant const RenderParams* p, const StrategyMis* m,
                                    SubpathState* st, float fwd, float rev, float cos_out,
                                    int delta) {
  if (delta) {
    st->dvcm = 0.0f;
    st->dvc *= bdpt_mis(p, cos_out);
    st->dvm *= bdpt_mis(p, cos_out);
    return;
  }
  const float g = bdpt_mis(p, cos_out / fwd), r = bdpt_mis(p, rev);
  st->dvc = g * (st->dvc * r + st->dvcm + m->vm);
  st->dvm = g * (st->dvm * r + st->dvcm * m->vc + m->vm_one);
  st->dvcm = bdpt_mis(p, 1.0f / fwd);
}

/* The MIS update of a subpath scattering at vertex sh (oriented to wo) into bs; the walk
 * (stages/walk.cl) does the rest of the scattering. */
static inline void bdpt_mis_scatter_sample(__constant const RenderParams* p, const StrategyMis* m,
                                           SubpathState* st, const SurfaceHit* sh, float3 wo,
                                           const BsdfSample* bs) {
  bdpt_mis_scatter(p, m, st, bs->pdf_w, bs->is_delta ? bs->pdf_w : bsdf_pdf_w(sh, bs->wi, wo),
                   fabs(dot(sh->ng, bs->wi)), bs->is_delta);
}

/* A light subpath's dVC and dVM are affine in vm and vc: the updates above add vm to dVC and
 * dVCM vc to dVM, and dVCM depends on neither (with merge_first no vm at all: its slope stays
 * 0, and the rebase moves dVM alone). EtaSlopes carries d dVC / d vm and d dVM / d vc
 * beside the state, so that a subpath traced with one eta can be weighted for a camera path
 * whose pixel merges with another (vcm's per-pixel radius, kernels/integrators/vcm/vcm_path.cl):
 * eta_rebase moves the state by (vm' - vm) and (vc' - vc) along them. */
typedef struct EtaSlopes {
  float dvc_vm;
  float dvm_vc;
} EtaSlopes;

/* At the light: dVM = dVC vc, dVC holds no vm. */
static inline EtaSlopes eta_slopes_start(const SubpathState* st) {
  EtaSlopes e;
  e.dvc_vm = 0.0f;
  e.dvm_vc = st->dvc;
  return e;
}

/* bdpt_mis_arrive's division by the cosine at the hit. */
static inline void eta_slopes_arrive(__constant const RenderParams* p, EtaSlopes* e, float cos_in) {
  const float c = bdpt_mis(p, cos_in);
  e->dvc_vm /= c;
  e->dvm_vc /= c;
}

/* bdpt_mis_scatter's update with factors m (vm's term there when m's vm_one is 1), with the
 * state's dVCM before it (dvcm). */
static inline void eta_slopes_scatter(__constant const RenderParams* p, const StrategyMis* m,
                                      EtaSlopes* e, float dvcm, float fwd, float rev,
                                      float cos_out, int delta) {
  if (delta) {
    e->dvc_vm *= bdpt_mis(p, cos_out);
    e->dvm_vc *= bdpt_mis(p, cos_out);
    return;
  }
  const float g = bdpt_mis(p, cos_out / fwd), r = bdpt_mis(p, rev);
  e->dvc_vm = g * (e->dvc_vm * r + m->vm_one);
  e->dvm_vc = g * (e->dvm_vc * r + dvcm);
}

/* The state a light subpath traced with the factors of `from` would have had with those of
 * `to`. */
static inline SubpathState eta_rebase(SubpathState st, EtaSlopes e, const StrategyMis* from,
                                      const StrategyMis* to) {
  st.dvc += (to->vm - from->vm) * e.dvc_vm;
  st.dvm += (to->vc - from->vc) * e.dvm_vc;
  return st;
}

/* s = 0: the camera subpath (state cam, after arriving) hit a light. q: the light's densities
 * for that point (direct per area or, for the environment, per steradian). */
static inline float bdpt_weight_hit_light(__constant const RenderParams* p, const SubpathState* cam,
                                          float direct, float emit_w) {
  const float w_camera = bdpt_mis(p, direct) * cam->dvcm + bdpt_mis(p, emit_w) * cam->dvc;
  return 1.0f / (1.0f + w_camera);
}

/* s = 1: next-event estimation from a camera vertex. pdf_w: light_illuminate's solid-angle
 * density (0 for delta lights, which BSDF sampling cannot find); direct_w: the same density in
 * SmallVCM's convention (a point light's delta position: selection * d^2); fwd, rev: the
 * camera vertex's BSDF densities towards the light and back; cos_here: geometric cosine at
 * the camera vertex. */
static inline float bdpt_weight_nee(__constant const RenderParams* p, const StrategyMis* m,
                                    const SubpathState* cam, float pdf_w, int delta, float direct_w,
                                    float emit_w, float cos_light, float fwd, float rev,
                                    float cos_here) {
  const float w_light = delta ? 0.0f : bdpt_mis(p, fwd / pdf_w);
  const float w_camera = bdpt_mis(p, emit_w * cos_here / (direct_w * cos_light)) *
                         (cam->dvcm + cam->dvc * bdpt_mis(p, rev) + m->vm);
  return 1.0f / (w_light + 1.0f + w_camera);
}

/* t = 1: a light vertex connected to the camera. camera_pdf_a: the density with which a camera
 * ray would find the vertex, per unit area (pdf_camera_film cos / d^2; per light path once
 * divided by m's light_per_pixel);
 * rev: the vertex's density of scattering back along the light subpath given the camera side. */
static inline float bdpt_weight_camera(__constant const RenderParams* p, const StrategyMis* m,
                                       const SubpathState* light, float camera_pdf_a, float rev) {
  const float w_light = bdpt_mis(p, camera_pdf_a / m->light_per_pixel) *
                        (light->dvcm + light->dvc * bdpt_mis(p, rev) + m->vm);
  return 1.0f / (w_light + 1.0f);
}

/* s >= 2, t >= 2: camera vertex and light vertex joined by an edge. *_fwd_a: each end's BSDF
 * density of sampling the other end, per unit area; *_rev: each end's density of scattering
 * back along its own subpath given the edge. */
static inline float bdpt_weight_connect(__constant const RenderParams* p, const StrategyMis* m,
                                        const SubpathState* cam, const SubpathState* light,
                                        float cam_fwd_a, float cam_rev, float light_fwd_a,
                                        float light_rev) {
  /* Merging at the light vertex: none with merge_first (the camera vertex comes first). */
  const float vm_light = m->merge_first ? 0.0f : m->vm;
  const float w_light =
      bdpt_mis(p, cam_fwd_a) * (light->dvcm + light->dvc * bdpt_mis(p, light_rev) + vm_light);
  const float w_camera =
      bdpt_mis(p, light_fwd_a) * (cam->dvcm + cam->dvc * bdpt_mis(p, cam_rev) + m->vm);
  return 1.0f / (w_light + 1.0f + w_camera);
}

/* Merging a light vertex (state light) at camera vertex cam: fwd, rev the camera vertex's
 * BSDF densities towards the light vertex's incoming direction and back (solid angle). */
static inline float vcm_weight_merge(__constant const RenderParams* p, const StrategyMis* m,
                                     const SubpathState* cam, const SubpathState* light, float fwd,
                                     float rev) {
  const float w_light = light->dvcm * m->vc + light->dvm * bdpt_mis(p, fwd);
  const float w_camera = cam->dvcm * m->vc + cam->dvm * bdpt_mis(p, rev);
  return 1.0f / (w_light + 1.0f + w_camera);
}

/* Whether strategy (s, t) contributes (--bdpt-strategy), and with which weight. */
static inline float bdpt_strategy_weight(const StrategyMis* m, u32 s, u32 t, float w) {
  if (m->only_s == BDPT_ALL_STRATEGIES) return w;
  if (s != m->only_s || t != m->only_t) return 0.0f;
  return m->unweighted ? 1.0f : w;
}

#endif
