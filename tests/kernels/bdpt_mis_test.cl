/* Kernels for tests/bdpt_mis_test.cpp: BDPT's recursive MIS weights
 * (kernels/integrators/stages/vertex_mis.cl) against the weights computed from whole-path densities.
 *
 * Each work-item samples one complete path x0 ... xm by BSDF sampling from the camera
 * (x0 the pinhole, xm the first front-face emitter hit, every vertex with a non-delta lobe,
 * 2 <= m <= MIS_TEST_MAX_EDGES) and writes, for that one path,
 *   - rec[s], s = 0 .. m: the recursive weight of strategy (s, t = m + 1 - s), computed by
 *     replaying the light subpath xm, xm-1, ... and the camera subpath x0, x1, ... over the
 *     same vertices with mis.cl's functions, called with the arguments that
 *     kernels/integrators/estimators/bdpt/light_path.cl and camera_path.cl pass, every distance,
 *     direction and density recomputed from the vertex positions;
 *   - rec_raw[s]: the same with the camera subpath's own hit.t, ray direction and bs.pdf_w
 *     in bdpt_mis_arrive / bdpt_mis_scatter, as the integrator has them (they differ from
 *     the positions' by the ray origin's offset, which matters at grazing angles);
 *   - pcam[i], i = 1 .. m: the area density with which the camera subpath samples xi
 *     (pcam[1] per film: camera_ray_pdf_w cos / d^2; the host scales it to a pixel);
 *   - plight[i], i = 1 .. m: the area density with which the light subpath samples xi
 *     (plight[m]: light_illuminate's / light_emit's density of the point, pdf_select / area);
 *   - pcam[0], plight[0]: the largest relative difference along the path between hit.t and
 *     the vertex distance, and between bs.pdf_w and bsdf_pdf_w between the vertices;
 *   - with merging (eta > 0: vcm's weights, eta = pi r^2 N_merge), rec_vm[k], k = 1 .. m - 1:
 *     the recursive weight of merging the light subpath's vertex x_k at the camera
 *     subpath's x_k, as kernels/integrators/vcm/vcm_path.cl computes it; every strategy's
 *     weight (rec) then carries the merging terms too. With eta_traced > 0 the light subpath
 *     is traced with the factors of eta_traced instead and moved to eta's along its
 *     EtaSlopes (eta_rebase) wherever it is weighted, as vcm's per-pixel radii do. With
 *     merge_first (--vcm-merge first) merging is made at the first non-delta camera vertex
 *     alone (rec_vm[1] here) and the factors are those of stages/vertex_mis.cl for it.
 * The host forms the explicit weights from pcam and plight in double precision.
 *
 * Slot layout: MIS_TEST_SLOTS floats per work-item for each of rec, rec_raw, pcam, plight;
 * meta[4i] = m (0: no usable path), meta[4i + 1] = status (MIS_TEST_*), meta[4i + 2] = the
 * number of vertices where the path passes through the surface (refraction). */
#include "bsdf/bsdf.cl"
#include "camera/camera_importance.cl"
#include "core/ray.cl"
#include "integrators/stages/vertex_mis.cl"
#include "light/light.cl"
#include "material/material.cl"
#include "sampler/sampler.cl"

#define MIS_TEST_MAX_EDGES 6
#define MIS_TEST_SLOTS 8

#define MIS_TEST_OK 1
#define MIS_TEST_NO_PATH 0           /* escaped, too long, absorbed, delta lobe, or m = 1 */
#define MIS_TEST_CAMERA_INVALID 2    /* camera_connect refused x1 (edge of the film) */
#define MIS_TEST_NO_LIGHT_PDF 3      /* the emitter hit has no light density */

inline float3 mis_test_dir(float3 from, float3 to) { return normalize(to - from); }

inline float mis_test_dist2(float3 a, float3 b) {
  const float3 d = b - a;
  return dot(d, d);
}

/* The camera subpath's MIS state along x1, ..., xm, updated as camera_path.cl updates it,
 * and the weights of the strategies s = 0 .. m - 1 that end at its vertices: s = 0 (the
 * emitter hit at xm), s = 1 (next-event estimation at x(m-1) that picked xm), s = m - k >= 2
 * (a connection from xk to light vertex x(k+1), whose light-side state is lstate[k+1]).
 * raw = 0: every input from the vertex positions (distances, directions, bsdf_pdf_w of the
 * scattered direction), so all strategies see one set of numbers; raw = 1: the hit distance
 * hit.t, the ray direction and bs.pdf_w of the sampled direction, as the integrator passes
 * them to bdpt_mis_arrive and bdpt_mis_scatter. */
inline void mis_test_camera_replay(__constant const RenderParams* params, const SceneView* s, int m,
                                   const float3* x, const SurfaceHit* vc, const SurfaceHit* vl,
                                   const SubpathState* lstate, u32 light_tri, float3 dir0,
                                   const float* hit_t, const float3* wo_cam, const float* fwd_cam,
                                   const float3* wi_cam, int raw, const StrategyMis* mm, float* rec,
                                   float* rec_vm) {
  int specular = 1; /* no non-delta camera vertex yet (merge_first merges at the first) */
  SubpathState st;
  st.beta = (float3)(1.0f);
  st.dvcm = bdpt_mis(params, mm->light_per_pixel /
                                 camera_ray_pdf_w(&params->camera, raw ? dir0 : mis_test_dir(x[0], x[1])));
  st.dvc = 0.0f;
  st.dvm = 0.0f;
  for (int k = 1; k <= m; ++k) {
    const float3 wo = raw ? wo_cam[k] : mis_test_dir(x[k], x[k - 1]);
    const float cos_in = fabs(dot(vc[k].ng, wo));
    bdpt_mis_arrive(params, &st, raw ? hit_t[k] : sqrt(mis_test_dist2(x[k - 1], x[k])), cos_in, 1);
    if (k == m) {
      /* s = 0: the emitter hit (k > 1 here). */
      const LightPdfs q = light_pdfs_area(s, light_tri, cos_in);
      rec[0] = bdpt_weight_hit_light(params, &st, q.direct, q.emit_w);
      break;
    }
    const SurfaceHit* sh = &vc[k];
    const int first = specular && bsdf_has_smooth_lobe(sh);
    if (bsdf_has_smooth_lobe(sh)) specular = 0;
    /* The factors at x_k, as vcm_camera_path takes them. */
    const StrategyMis mk = mis_at_camera_vertex(mm, first);
    if (first || !mm->merge_first) {
      /* Merging light vertex x_k (state lstate[k], arrived from x(k+1)) at camera vertex x_k. */
      const float3 y_wo = mis_test_dir(x[k], x[k + 1]);
      rec_vm[k] = vcm_weight_merge(params, &mk, &st, &lstate[k], bsdf_pdf_w(sh, wo, y_wo),
                                   bsdf_pdf_w(sh, y_wo, wo));
    }
    if (k == m - 1) {
      /* s = 1: next-event estimation that picked the path's own light point xm. */
      const float3 d = x[m] - x[k];
      const float dist = length(d);
      const float3 wi = d / dist;
      const LightPdfs q = light_pdfs_area(s, light_tri, fabs(dot(vc[m].ng, wi)));
      /* light_illuminate's pdf_w for that point: pdf_select dist^2 / (area cos_light). */
      const float pdf_w = q.direct * dist * dist / q.cos_light;
      const float direct_w = q.finite ? q.direct * dist * dist / q.cos_light : q.direct;
      rec[1] = bdpt_weight_nee(params, &mk, &st, pdf_w, 0, direct_w, q.emit_w, q.cos_light,
                               bsdf_pdf_w(sh, wo, wi), bsdf_pdf_w(sh, wi, wo), fabs(dot(sh->ng, wi)));
    } else {
      /* s = m - k >= 2: a connection to light vertex x(k+1), as bdpt_connect makes it. */
      const SurfaceHit* y = &vl[k + 1];
      const float3 y_wo = mis_test_dir(x[k + 1], x[k + 2]);
      const float3 d = y->p - sh->p;
      const float dist2 = dot(d, d);
      const float3 dc = d / sqrt(dist2);
      const float cos_cam = fabs(dot(sh->ng, dc)), cos_l = fabs(dot(y->ng, dc));
      rec[m - k] = bdpt_weight_connect(params, &mk, &st, &lstate[k + 1],
                                       bsdf_pdf_w(sh, wo, dc) * cos_l / dist2, bsdf_pdf_w(sh, dc, wo),
                                       bsdf_pdf_w(y, y_wo, -dc) * cos_cam / dist2,
                                       bsdf_pdf_w(y, -dc, y_wo));
    }
    const float3 wi = raw ? wi_cam[k] : mis_test_dir(x[k], x[k + 1]);
    const float fwd = raw ? fwd_cam[k] : bsdf_pdf_w(sh, wo, wi);
    bdpt_mis_scatter(params, &mk, &st, fwd, bsdf_pdf_w(sh, wi, wo), fabs(dot(sh->ng, wi)), 0);
  }
}

__kernel void bdpt_mis_paths(SCENE_KERNEL_ARGS __constant const RenderParams* params, u32 n,
                             float eta, float eta_traced, int merge_first, float light_per_pixel,
                             __global float* rec_out,
                             __global float* rec_raw_out,
                             __global float* rec_vm_out, __global float* pcam_out,
                             __global float* plight_out, __global int* meta) {
  const u32 gid = get_global_id(0);
  if (gid >= n) return;
  const SceneView s = SCENE_VIEW();
  StrategyMis mm = mis_all_strategies();
  if (eta > 0.0f) mm = mis_merging(bdpt_mis(params, eta), bdpt_mis(params, 1.0f / eta), merge_first);
  mm.light_per_pixel = light_per_pixel; /* vcm's --vcm-light-paths */
  StrategyMis mt = mm; /* the light subpath's factors as traced */
  if (eta_traced > 0.0f)
    mt = mis_merging(bdpt_mis(params, eta_traced), bdpt_mis(params, 1.0f / eta_traced), merge_first);
  mt.light_per_pixel = light_per_pixel;
  mt = mis_light_side(&mt);
  for (int i = 0; i < MIS_TEST_SLOTS; ++i) {
    rec_out[gid * MIS_TEST_SLOTS + i] = 0.0f;
    rec_vm_out[gid * MIS_TEST_SLOTS + i] = 0.0f;
    rec_raw_out[gid * MIS_TEST_SLOTS + i] = 0.0f;
    pcam_out[gid * MIS_TEST_SLOTS + i] = 0.0f;
    plight_out[gid * MIS_TEST_SLOTS + i] = 0.0f;
  }
  meta[4 * gid] = 0;
  meta[4 * gid + 1] = MIS_TEST_NO_PATH;
  meta[4 * gid + 2] = 0;
  meta[4 * gid + 3] = 0;

  /* 1. The path, sampled from the camera as camera_path.cl samples it. */
  const Sampler sampler = sampler_init(params, gid, 0u);
  const float2 film = 2.0f * sample_2d(&sampler, DIM_PIXEL) - (float2)(1.0f);
  float3 org, dir;
  camera_ray(&params->camera, film, (float2)(0.5f), &org, &dir);
  const float3 dir0 = dir;

  float3 x[MIS_TEST_MAX_EDGES + 1];
  SurfaceHit vc[MIS_TEST_MAX_EDGES + 1];  /* camera side: oriented to wo towards x(i-1) */
  float3 wo_cam[MIS_TEST_MAX_EDGES + 1];  /* -ray direction at each hit */
  float hit_t[MIS_TEST_MAX_EDGES + 1];
  float fwd_cam[MIS_TEST_MAX_EDGES + 1];  /* bs.pdf_w of the sampled direction at xi */
  float3 wi_cam[MIS_TEST_MAX_EDGES + 1];  /* the sampled direction at xi */
  x[0] = org;
  int m = 0;
  for (int k = 1; k <= MIS_TEST_MAX_EDGES; ++k) {
    Hit hit;
    if (!intersect_closest(&s, org, dir, INFINITY, &hit)) return;
    SurfaceHit sh = surface_shade(&s, &hit, org, dir);
    const float3 wo = -dir;
    x[k] = sh.p;
    hit_t[k] = hit.t;
    wo_cam[k] = wo;
    if (!is_black(light_radiance(&s, &sh, wo))) {
      vc[k] = sh; /* not oriented: the camera subpath ends here (s = 0) */
      m = k;
      break;
    }
    bsdf_orient(&sh, wo);
    if (!bsdf_has_smooth_lobe(&sh)) return;
    vc[k] = sh;
    if (k == MIS_TEST_MAX_EDGES) return;
    const BsdfSample bs =
        bsdf_sample(&sh, wo, sample_2d(&sampler, bounce_dim((u32)k - 1u, DIM_BSDF_DIR)),
                    sample_1d(&sampler, bounce_dim((u32)k - 1u, DIM_BSDF_LOBE)), TRANSPORT_RADIANCE);
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight) || bs.is_delta) return;
    fwd_cam[k] = bs.pdf_w;
    wi_cam[k] = bs.wi;
    org = offset_ray_origin(sh.p, dot(bs.wi, sh.ng) >= 0.0f ? sh.ng : -sh.ng);
    dir = bs.wi;
  }
  if (m < 2) return;

  const u32 light_tri = vc[m].triangle;
  const float3 to_prev_m = mis_test_dir(x[m], x[m - 1]);
  const float cos_light = fabs(dot(vc[m].ng, to_prev_m));
  const LightPdfs qa = light_pdfs_area(&s, light_tri, cos_light);
  if (!(qa.direct > 0.0f && qa.emit_w > 0.0f)) {
    meta[4 * gid + 1] = MIS_TEST_NO_LIGHT_PDF;
    return;
  }

  /* Light-side copies of the vertices, oriented to wo towards x(i+1). */
  SurfaceHit vl[MIS_TEST_MAX_EDGES + 1];
  for (int i = 1; i < m; ++i) {
    vl[i] = vc[i];
    bsdf_orient(&vl[i], mis_test_dir(x[i], x[i + 1]));
  }

  /* 2. Per-vertex area densities of the two subpaths (the explicit weights' inputs). */
  float pcam[MIS_TEST_SLOTS], plight[MIS_TEST_SLOTS];
  for (int i = 0; i < MIS_TEST_SLOTS; ++i) pcam[i] = plight[i] = 0.0f;
  {
    const float3 d01 = mis_test_dir(x[0], x[1]);
    pcam[1] = camera_ray_pdf_w(&params->camera, d01) * fabs(dot(vc[1].ng, d01)) /
              mis_test_dist2(x[0], x[1]);
  }
  for (int i = 2; i <= m; ++i) {
    const float3 wo = mis_test_dir(x[i - 1], x[i - 2]), wi = mis_test_dir(x[i - 1], x[i]);
    pcam[i] = bsdf_pdf_w(&vc[i - 1], wo, wi) * fabs(dot(vc[i].ng, wi)) / mis_test_dist2(x[i - 1], x[i]);
  }
  plight[m] = qa.direct;
  plight[m - 1] = (qa.emit_w / qa.direct) * fabs(dot(vc[m - 1].ng, to_prev_m)) /
                  mis_test_dist2(x[m], x[m - 1]);
  for (int j = m - 2; j >= 1; --j) {
    const float3 wo = mis_test_dir(x[j + 1], x[j + 2]), wi = mis_test_dir(x[j + 1], x[j]);
    plight[j] = bsdf_pdf_w(&vl[j + 1], wo, wi) * fabs(dot(vc[j].ng, wi)) / mis_test_dist2(x[j + 1], x[j]);
  }

  /* 3. The light subpath's MIS state along x(m-1), ..., x1, as light_path.cl updates it,
   * from the LightEmission that light_emit would have returned for this point and ray. */
  float rec[MIS_TEST_SLOTS];
  for (int i = 0; i < MIS_TEST_SLOTS; ++i) rec[i] = 0.0f;
  SubpathState lstate[MIS_TEST_MAX_EDGES + 1];
  {
    LightEmission e;
    e.p = x[m];
    e.dir = to_prev_m;
    e.Le = vc[m].emission;
    e.light = (u32)s.triangle_light[light_tri];
    e.pdf_select = s.lights[e.light].pdf_select;
    e.pdf_a = 1.0f / triangle_area(&s, light_tri);
    e.pdf_w = ((s.materials[vc[m].material].flags & MATERIAL_DOUBLE_SIDED) ? 0.5f : 1.0f) *
              warp_cosine_hemisphere_pdf(cos_light);
    e.cos_light = cos_light;
    e.is_delta_pos = 0;
    e.is_delta_dir = 0;
    const LightPdfs q = light_pdfs_emission(&s, &e);
    SubpathState st;
    st.beta = (float3)(1.0f);
    st.dvcm = bdpt_mis(params, q.direct / q.emit_w);
    st.dvc = (e.is_delta_pos || e.is_delta_dir) ? 0.0f : bdpt_mis(params, q.cos_light / q.emit_w);
    st.dvm = st.dvc * mt.vc;
    EtaSlopes es = eta_slopes_start(&st);
    for (int depth = 1; depth <= m - 1; ++depth) {
      const int j = m - depth;
      const float3 wo = mis_test_dir(x[j], x[j + 1]);
      bdpt_mis_arrive(params, &st, sqrt(mis_test_dist2(x[j], x[j + 1])), fabs(dot(vl[j].ng, wo)),
                      depth > 1 || q.finite);
      eta_slopes_arrive(params, &es, fabs(dot(vl[j].ng, wo)));
      lstate[j] = eta_rebase(st, es, &mt, &mm);
      if (j == 1) {
        /* t = 1: bdpt_connect_camera at x1 (strategy s = m). */
        const CameraConnection c =
            camera_connect(&params->camera, params->width, params->height, x[1], (float2)(0.5f));
        if (!c.valid) {
          meta[4 * gid + 1] = MIS_TEST_CAMERA_INVALID;
          return;
        }
        const float camera_pdf_a = c.pdf_w * fabs(dot(vl[1].ng, c.wi)) / (c.dist * c.dist);
        const float rev = bsdf_pdf_w(&vl[1], c.wi, wo);
        rec[m] = bdpt_weight_camera(params, &mm, &lstate[j], camera_pdf_a, rev);
      } else {
        const float3 wi = mis_test_dir(x[j], x[j - 1]);
        const float fwd = bsdf_pdf_w(&vl[j], wo, wi), rev = bsdf_pdf_w(&vl[j], wi, wo);
        eta_slopes_scatter(params, &mt, &es, st.dvcm, fwd, rev, fabs(dot(vl[j].ng, wi)), 0);
        bdpt_mis_scatter(params, &mt, &st, fwd, rev, fabs(dot(vl[j].ng, wi)), 0);
      }
    }
  }

  /* 4. The camera subpath's MIS state along x1, ..., xm and the strategies s < m that end
   * at its vertices: with every input recomputed from the vertex positions (rec, the test
   * proper), and with the ray's own inputs as the integrator has them (rec_raw). */
  float rec_raw[MIS_TEST_SLOTS], rec_vm[MIS_TEST_SLOTS], rec_vm_raw[MIS_TEST_SLOTS];
  for (int i = 0; i < MIS_TEST_SLOTS; ++i) {
    rec_raw[i] = rec[i];
    rec_vm[i] = rec_vm_raw[i] = 0.0f;
  }
  mis_test_camera_replay(params, &s, m, x, vc, vl, lstate, light_tri, dir0, hit_t, wo_cam,
                         fwd_cam, wi_cam, 0, &mm, rec, rec_vm);
  mis_test_camera_replay(params, &s, m, x, vc, vl, lstate, light_tri, dir0, hit_t, wo_cam,
                         fwd_cam, wi_cam, 1, &mm, rec_raw, rec_vm_raw);

  /* Slot 0 of pcam and plight (unused by the weights): how far the integrator's own inputs
   * are from those recomputed from the positions (relative: hit.t against the distance,
   * bs.pdf_w against bsdf_pdf_w between the vertices), for the report. */
  {
    float dt = 0.0f, dp = 0.0f;
    for (int k = 1; k <= m; ++k) {
      const float d = sqrt(mis_test_dist2(x[k - 1], x[k]));
      dt = fmax(dt, fabs(hit_t[k] - d) / d);
      if (k < m) {
        const float pw = bsdf_pdf_w(&vc[k], mis_test_dir(x[k], x[k - 1]), mis_test_dir(x[k], x[k + 1]));
        dp = fmax(dp, fabs(fwd_cam[k] - pw) / fwd_cam[k]);
      }
    }
    pcam[0] = dt;
    plight[0] = dp;
  }
  for (int i = 0; i < MIS_TEST_SLOTS; ++i) {
    rec_out[gid * MIS_TEST_SLOTS + i] = rec[i];
    rec_raw_out[gid * MIS_TEST_SLOTS + i] = rec_raw[i];
    rec_vm_out[gid * MIS_TEST_SLOTS + i] = rec_vm[i];
    pcam_out[gid * MIS_TEST_SLOTS + i] = pcam[i];
    plight_out[gid * MIS_TEST_SLOTS + i] = plight[i];
  }
  int refractions = 0;
  for (int k = 1; k < m; ++k)
    refractions += dot(vc[k].ng, x[k - 1] - x[k]) * dot(vc[k].ng, x[k + 1] - x[k]) < 0.0f;
  meta[4 * gid] = m;
  meta[4 * gid + 1] = MIS_TEST_OK;
  meta[4 * gid + 2] = refractions;
}
