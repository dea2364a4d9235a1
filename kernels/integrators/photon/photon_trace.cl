/* Photon emission (Jensen 2001, ch. 5): a path leaves a light exactly as a light tracer's
 * does (light_emit, importance-mode BSDF sampling with Veach's shading-normal correction;
 * kernels/integrators/light_trace.cl), and at every hit with a non-delta BSDF it stores a
 * photon: position, incoming direction, the flux it carries and the geometric normal, and
 * whether every scattering before it was a delta one (L S+ D, a caustic photon). Russian
 * roulette by albedo from the first bounce: a photon goes on with probability
 * min(1, max(f cos / pdf)) and its flux is divided by that, so a white diffuse surface
 * passes it on unchanged.
 *
 * The flux of a path is Le cos / (p_select p_area p_dir) divided by the number of paths
 * emitted (`inv_paths`), so the photons of a map sum to the power arriving at surfaces. */
#ifndef CLPT_INTEGRATORS_PHOTON_PHOTON_TRACE_CL
#define CLPT_INTEGRATORS_PHOTON_PHOTON_TRACE_CL

#include "integrators/light_trace.cl"
#include "material/volume.cl"
#include "integrators/photon/glossy.cl"
#include "shared/photon_types.h"

inline void photon_store(__global Photon* out, volatile __global u32* count, u32 capacity,
                         const SurfaceHit* sh, float3 wi, float3 power, u32 flags) {
  const u32 slot = atomic_inc(count);
  if (slot >= capacity) return; /* full: the host sees count > capacity and says so */
  __global Photon* ph = out + slot;
  vstore3(sh->p, 0, ph->p);
  ph->flags = flags;
  vstore3(power, 0, ph->power);
  ph->pad0 = 0.0f;
  vstore3(wi, 0, ph->wi);
  ph->pad1 = 0.0f;
  vstore3(sh->ng, 0, ph->n);
  ph->pad2 = 0.0f;
}

/* One photon path. store: PHOTON_STORE_* mask (caustic photons only, for the caustic map's
 * pass; no first-hit photons, for SPPM whose direct light is NEE's). */
inline void photon_trace(__constant const RenderParams* p, const SceneView* s,
                         const Sampler* sampler, float inv_paths, u32 store,
                         __global Photon* out, volatile __global u32* count, u32 capacity,
                         u32* rays) {
  if (s->num_lights == 0u) return;
  const int caustic_only = (store & PHOTON_STORE_CAUSTIC_ONLY) != 0u;
  const u32 first_stored = (store & PHOTON_STORE_SKIP_DIRECT) ? 2u : 1u;
  const LightEmission e =
      light_emit(s, sample_1d(sampler, bounce_dim(0u, DIM_LIGHT_SELECT)),
                 sample_2d(sampler, DIM_LT_EMIT_POS), sample_2d(sampler, DIM_LT_EMIT_DIR));
  if (!(e.pdf_a > 0.0f && e.pdf_w > 0.0f && e.pdf_select > 0.0f) || is_black(e.Le)) return;
  float3 power = e.Le * (e.cos_light * inv_paths / (e.pdf_select * e.pdf_a * e.pdf_w));
  float3 org = light_emission_origin(s, &e), dir = e.dir;
  int specular_only = 1; /* every scattering so far was a delta one */
  SurfaceHit prev;
  for (u32 depth = 1u; depth <= p->max_depth; ++depth) {
    Hit hit;
    ++*rays;
    if (!intersect_closest(s, org, dir, INFINITY, &hit)) break;
    if (depth > 1u) power *= volume_transmittance(s, &prev, dir, hit.t);
    SurfaceHit sh = surface_shade(s, &hit, org, dir);
    const float3 wo = -dir;
    bsdf_orient(&sh, wo);
    /* Glossy vertices hold no photons: no density estimate is made there
     * (kernels/integrators/photon/visible_point.cl). */
    const int glossy = photon_glossy(&sh);
    if (bsdf_has_smooth_lobe(&sh) && !glossy) {
      const int caustic = specular_only && depth > 1u;
      if ((caustic || !caustic_only) && depth >= first_stored) {
        const float coverage = alpha_coverage(s, hit.triangle, hit.b1, hit.b2);
        if (coverage > 0.0f)
          photon_store(out, count, capacity, &sh, wo, power / coverage,
                       (caustic ? PHOTON_CAUSTIC : 0u) | (depth << PHOTON_BOUNCE_SHIFT));
      }
    }
    if (depth >= p->max_depth) break;
    const BsdfSample bs =
        bsdf_sample(&sh, wo, sample_2d(sampler, bounce_dim(depth, DIM_BSDF_DIR)),
                    sample_1d(sampler, bounce_dim(depth, DIM_BSDF_LOBE)), TRANSPORT_IMPORTANCE);
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight)) break;
    const float3 scatter = bs.weight * lt_shading_correction(&sh, wo, bs.wi);
    const float survive = fmin(1.0f, max_component(scatter));
    if (!(sample_1d(sampler, bounce_dim(depth, DIM_RR)) < survive)) break;
    power *= scatter / survive;
    specular_only = specular_only && (bs.is_delta || glossy);
    /* A caustic pass stops once a path can no longer make caustic photons. */
    if (caustic_only && !specular_only) break;
    prev = sh;
    org = offset_ray_origin_towards(sh.p, sh.ng, bs.wi);
    dir = bs.wi;
  }
}

#endif
