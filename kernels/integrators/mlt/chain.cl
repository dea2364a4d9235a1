/* One Metropolis step of a chain (Metropolis et al. 1953; Veach's expected values, Veach
 * 1997 §11.5): propose, accept with a = min(1, I(y) / I(x)), and splat both the proposal y
 * (weight a) and the current state x (weight 1 - a), each as C / I times the pass's scale, so
 * the image is the chain's density (I / b) times b C / I = C whatever a is. The current
 * state's weights are gathered while it stays current and splatted once, when it is left or
 * at the end of the launch. */
#ifndef CLPT_INTEGRATORS_MLT_CHAIN_CL
#define CLPT_INTEGRATORS_MLT_CHAIN_CL

#include "film/splat.cl"
#include "integrators/mlt/pss_path.cl"

/* Splats the current state's gathered weight. */
inline void mlt_flush(MltChain* ch, float scale, __global float4* splat) {
  if (ch->weight > 0.0f && ch->luminance > 0.0f)
    film_splat(splat, ch->pixel, vload3(0, ch->color) * (ch->weight * scale / ch->luminance));
  ch->weight = 0.0f;
}

inline void mlt_step(const SceneView* s, __constant const RenderParams* p,
                     __constant const MltParams* m, MltChain* ch, __global PssCoord* coords,
                     u32 chain_key, __global float4* splat, u32* rays) {
  const Sampler proposal =
      pss_propose(ch, coords, m->dim_stride, m->dims, chain_key, m->large_step, m->sigma);
  const PssPath y = pss_path(s, p, &proposal, rays);
  const float a = pss_acceptance(y.target, ch->luminance);
  if (y.target > 0.0f) film_splat(splat, y.pixel, y.L * (a * m->splat_scale / y.target));
  ch->weight += 1.0f - a;
  const bool accepted = pss_accept_u(&proposal) < a;
  if (proposal.large_step) {
    ch->large_proposed += 1u;
    ch->large_accepted += accepted ? 1u : 0u;
  } else {
    ch->small_proposed += 1u;
    ch->small_accepted += accepted ? 1u : 0u;
  }
  if (accepted) {
    mlt_flush(ch, m->splat_scale, splat);
    vstore3(y.L, 0, ch->color);
    ch->luminance = y.target;
    ch->pixel = y.pixel;
    pss_accept(ch, &proposal);
  } else {
    pss_reject(ch, &proposal);
  }
}

#endif
