/* Photon emission (Jensen 2001, ch. 5): a path leaves a light (light_emit) and walks as
 * every light-side path does (importance-mode BSDF sampling with Veach's shading-normal
 * correction; kernels/integrators/stages/walk.cl, with the walk's WALK_RR_ALBEDO roulette), and at every hit with a non-delta BSDF it stores a
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

#include "integrators/estimators/photon/glossy.cl"
#include "integrators/stages/walk.cl"
#include "light/light.cl"
#include "shared/photon_types.h"

static inline void photon_store(__global Photon* out, volatile __global u32* count, u32 capacity,
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
static inline void photon_trace(__constant const RenderParams* p, const SceneView* s,
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
  const float3 power = e.Le * (e.cos_light * inv_paths / (e.pdf_select * e.pdf_a * e.pdf_w));
  PathWalk w = walk_from_light(e.p, light_emission_origin(s, &e), e.dir, power, 0u, WALK_RR_ALBEDO);
  int specular_only = 1; /* every scattering so far was a delta one */
  while (w.depth <= p->max_depth && walk_next(s, sampler, &w, rays)) {
    const u32 depth = w.depth;
    /* Glossy vertices hold no photons: no density estimate is made there
     * (kernels/integrators/estimators/photon/visible_point.cl). */
    const int glossy = photon_glossy(&w.sh);
    if (bsdf_has_smooth_lobe(&w.sh) && !glossy) {
      const int caustic = specular_only && depth > 1u;
      if ((caustic || !caustic_only) && depth >= first_stored) {
        const float coverage = alpha_coverage(s, w.hit.triangle, w.hit.b1, w.hit.b2);
        if (coverage > 0.0f)
          photon_store(out, count, capacity, &w.sh, w.wo, w.beta / coverage,
                       (caustic ? PHOTON_CAUSTIC : 0u) | (depth << PHOTON_BOUNCE_SHIFT));
      }
    }
    if (depth >= p->max_depth) break;
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
    specular_only = specular_only && (bs.is_delta || glossy);
    /* A caustic pass stops once a path can no longer make caustic photons. */
    if (caustic_only && !specular_only) break;
  }
}

#endif
