/* An irradiance record's hemisphere (Ward, Rubinstein and Clear 1988; Ward and Heckbert
 * 1992): M x N stratified cosine-weighted rays around the record's normal, stratum (j, k)
 * covering sin^2 theta in [j/M, (j+1)/M) and phi in [2 pi k/N, 2 pi (k+1)/N), each with the
 * same solid-angle-times-cosine share pi/(M N) of the hemisphere. Ray (j, k) returns
 * L_jk = L_ind(y) (ic_path.cl: y's radiance without its emission) and the distance r_jk to y.
 * Then
 *     E = pi/(M N) sum_jk L_jk
 *     R = M N / sum_jk 1/r_jk                       (harmonic mean; escaped rays add 0)
 *     grad_rot E = pi/(M N) sum_k v_k sum_j tan(theta_j) L_jk    (tan's mean over the stratum)
 *     grad_trans E = sum_k [ u_k 2pi/N sum_{j>=1} sin(theta_j-) cos^2(theta_j-)
 *                                    (L_jk - L_j-1,k) / min(r_jk, r_j-1,k)
 *                          + v_k- sum_j (sin theta_j+ - sin theta_j-)
 *                                    (L_jk - L_j,k-1) / min(r_jk, r_j,k-1) ]
 * with theta_j, theta_j- and theta_j+ the stratum's middle, lower and upper polar angles,
 * u_k the direction of the stratum's middle phi_k, v_k = u_k turned by 90 degrees about n,
 * v_k- that of its lower edge 2 pi k/N (Ward and Heckbert 1992, in the notation of Krivanek
 * et al.'s 2008 course notes). The azimuthal term is the cosine-weighted solid angle a
 * wall between strata sweeps as x moves across it, the integral of cos theta d theta / r
 * over the stratum: Ward and Heckbert's printed (cos theta_j- - cos theta_j+) / sin theta_j
 * lacks the cosine (Mitsuba 0.6's irradiance cache multiplies it by cos theta_j, the same to
 * first order), and made the gradient 1.5x too large under a ceiling of linear radiance
 * (tests/ic_test.cpp, TranslationalGradientUnderALinearCeiling). The rotational gradient is the derivative of E for a rotation
 * about the axis n x n' (dE = grad_rot . (n x n')); the lookup takes n_i x n. R is then
 * limited by the gradient (R <= E / |grad_trans E|, Krivanek et al. 2008) and clamped so that the validity radius a R lies within [min, max] spacing pixel footprints
 * (Tabellion and Lamorlette 2004 clamp in pixels likewise). */
#ifndef CLPT_INTEGRATORS_IC_RECORDS_CL
#define CLPT_INTEGRATORS_IC_RECORDS_CL

#include "integrators/ic/ic_path.cl"
#include "integrators/estimators/photon/estimate.cl"

/* The record frame's local direction of stratum (j, k) at offset u in it. */
static inline float3 ic_stratum_dir(u32 j, u32 k, u32 m, u32 n, float2 u) {
  const float s2 = ((float)j + u.x) / (float)m;
  const float2 phi = cos_sin_turns(((float)k + u.y) / (float)n);
  const float sin_t = sqrt(s2), cos_t = sqrt(fmax(0.0f, 1.0f - s2));
  return (float3)(phi * sin_t, cos_t);
}

/* The mean of tan(theta) over a stratum sin^2 theta in [lo, hi) under the cosine-weighted
 * measure (uniform in s = sin^2 theta): the integral of sqrt(s / (1 - s)) is
 * asin(sqrt(s)) - sqrt(s (1 - s)). Ward and Heckbert take tan at the stratum's middle, which
 * falls short at the horizon where tan grows without bound (by 10 % on a linear field with
 * 18 x 57 rays; tests/ic_test.cpp, RecordSumsOnALinearField). */
static inline float ic_stratum_tan(float lo, float hi) {
  const float a = asin(sqrt(lo)) - sqrt(lo * (1.0f - lo));
  const float b = asin(sqrt(hi)) - sqrt(hi * (1.0f - hi));
  return (b - a) / (hi - lo);
}

/* Ray q = j N + k of record rec: (L_jk, r_jk). sampler: the record's own. L_jk is the light
 * y reflects towards x without y's own emission (x's direct light): path traced from y, or
 * (ic->gather != IC_GATHER_PATHS) the global map's estimate at the first vertex y' neither
 * delta nor glossy the ray reaches, all the light y' reflects (photons of every bounce, as
 * pm's final gather reads it), plus, without a caustic map, the emission seen on the way
 * beyond y (L S+ D(x) light, which x's own NEE cannot find). */
static inline float4 ic_record_ray(__constant const RenderParams* p, const SceneView* s,
                                   __constant const IcParams* ic, const PhotonMap* map,
                                   __global const IcRecord* rec, u32 q, const Sampler* sampler,
                                   u32* rays) {
  const u32 j = q / ic->rays_phi, k = q % ic->rays_phi;
  const float3 n = vload3(0, rec->n), x = vload3(0, rec->p);
  const float3 dir =
      to_world(ic_stratum_dir(j, k, ic->rays_theta, ic->rays_phi, sample_2d(sampler, DIM_PIXEL)), n);
  const float3 org = offset_ray_origin(x, n);
  if (ic->gather != IC_GATHER_PATHS) {
    VisiblePoint y;
    const int emission =
        ic->gather == IC_GATHER_PHOTONS ? VP_EMISSION_BEYOND_FIRST : VP_EMISSION_NONE;
    float3 L = (float3)(0.0f);
    if (photon_visible_point(p, s, sampler, 0, org, dir, rec->depth + 1u, 0u, emission, rays, &y))
      L = y.beta * pm_estimate(p, map, &y, 1u, 0);
    L += y.L;
    return (float4)(is_finite3(L) ? L : (float3)(0.0f), y.t_first);
  }
  PathWalk w = walk_from_ray(x, org, dir, (float3)(1.0f), MEDIUM_NONE, rec->depth + 1u, 0u,
                             TRANSPORT_RADIANCE, WALK_RR_PATH);
  if (!walk_next(s, sampler, &w, rays)) return (float4)(0.0f, 0.0f, 0.0f, INFINITY);
  const float3 L = w.beta * ic_indirect_at(p, s, sampler, &w, rays);
  return (float4)(is_finite3(L) ? L : (float3)(0.0f), w.hit.t);
}

/* The record from its rays' results (M N of them, row j = 0 first): E, R and gradients,
 * averaged with the record's earlier batches (rec->rays of them so far). A new record holds
 * p, n, depth, pixel, rays = 0 and, in r, the pixel footprint at p. */
static inline void ic_finish_record(__constant const IcParams* ic, __global IcRecord* rec,
                                    __global const float4* ray) {
  const u32 m = ic->rays_theta, nphi = ic->rays_phi;
  const float share = PI_F / (float)(m * nphi);
  float3 e = (float3)(0.0f), rot[3], trans[3];
  for (int c = 0; c < 3; ++c) rot[c] = trans[c] = (float3)(0.0f);
  float inv_r = 0.0f;
  for (u32 k = 0; k < nphi; ++k) {
    const float phi = 2.0f * PI_F * ((float)k + 0.5f) / (float)nphi;
    const float phi_lo = 2.0f * PI_F * (float)k / (float)nphi;
    const float3 u_k = (float3)(cos(phi), sin(phi), 0.0f);
    const float3 v_k = (float3)(-sin(phi), cos(phi), 0.0f);
    const float3 v_lo = (float3)(-sin(phi_lo), cos(phi_lo), 0.0f);
    const u32 k_prev = (k + nphi - 1u) % nphi;
    float3 rot_k = (float3)(0.0f), radial = (float3)(0.0f), azimuthal = (float3)(0.0f);
    for (u32 j = 0; j < m; ++j) {
      const float4 here = ray[j * nphi + k];
      const float3 L = here.xyz;
      e += L;
      inv_r += 1.0f / here.w; /* 0 for an escaped ray */
      const float s2_lo = (float)j / (float)m, s2_hi = (float)(j + 1u) / (float)m;
      rot_k += ic_stratum_tan(s2_lo, s2_hi) * L;
      const float cos_lo = sqrt(1.0f - s2_lo), sin_lo = sqrt(s2_lo);
      if (j > 0u) {
        const float4 below = ray[(j - 1u) * nphi + k];
        const float r_min = fmin(here.w, below.w);
        if (r_min < INFINITY)
          radial += (sin_lo * cos_lo * cos_lo / r_min) * (L - below.xyz);
      }
      const float4 side = ray[j * nphi + k_prev];
      const float r_side = fmin(here.w, side.w);
      if (r_side < INFINITY && nphi > 1u)
        azimuthal += ((sqrt(s2_hi) - sin_lo) / r_side) * (L - side.xyz);
    }
    const float3 radial_w = (2.0f * PI_F / (float)nphi) * radial;
    rot[0] += rot_k.x * v_k;
    rot[1] += rot_k.y * v_k;
    rot[2] += rot_k.z * v_k;
    trans[0] += radial_w.x * u_k + azimuthal.x * v_lo;
    trans[1] += radial_w.y * u_k + azimuthal.y * v_lo;
    trans[2] += radial_w.z * u_k + azimuthal.z * v_lo;
  }
  /* This batch's estimates, then the running means with the batches before. */
  const float3 n = vload3(0, rec->n);
  float3 t, b;
  make_basis(n, &t, &b);
  const u32 before = rec->rays, now = m * nphi;
  const float w_old = (float)before / (float)(before + now), w_new = 1.0f - w_old;
  for (int c = 0; c < 3; ++c) {
    float3 rw = share * (rot[c].x * t + rot[c].y * b);
    float3 tw = trans[c].x * t + trans[c].y * b;
    rw = is_finite3(rw) ? rw : (float3)(0.0f);
    tw = is_finite3(tw) ? tw : (float3)(0.0f);
    /* A new record's old values are not read: they need not be numbers. */
    vstore3(before ? w_old * vload3(c, rec->rot) + w_new * rw : rw, c, rec->rot);
    vstore3(before ? w_old * vload3(c, rec->trans) + w_new * tw : tw, c, rec->trans);
  }
  vstore3(before ? w_old * vload3(0, rec->e) + w_new * (share * e) : share * e, 0, rec->e);
  if (before == 0u) {
    rec->footprint = rec->r; /* a candidate's r is its footprint */
    rec->inv_r_sum = 0.0f;
  }
  rec->inv_r_sum += inv_r;
  rec->rays = before + now;
  const float lo = ic->min_spacing * rec->footprint / ic->error;
  const float hi = ic->max_spacing * rec->footprint / ic->error;
  const float harmonic = rec->inv_r_sum > 0.0f ? (float)rec->rays / rec->inv_r_sum : INFINITY;
  /* The gradient limit: R <= E / |grad_trans E| (luminance), so the extrapolation changes
   * E by at most a E over the validity radius a R. Without it a record near a corner, whose
   * translational gradient is large and noisy (its 1 / min(r) terms), paints a blotch. */
  const float e_lum = luminance(vload3(0, rec->e));
  const float g_len = length(ic_luminance_gradient(rec->trans));
  const float limit = g_len > 0.0f ? e_lum / g_len : INFINITY;
  rec->r = clamp(fmin(harmonic, limit), lo, hi);
}

#endif
