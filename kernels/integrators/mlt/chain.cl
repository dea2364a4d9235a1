/* One Metropolis step of a chain (Metropolis et al. 1953): propose y, accept with
 * a = min(1, I(y) / I(x)), and splat both the proposal and the current state x with Veach's
 * expected values (Veach 1997 §11.5: y with weight a, x with 1 - a) combined by MIS with the
 * large steps seen as independent samples (Kelemen et al. 2002, §4.2): a large step's proposal
 * gets weight a + 1, and every splat is C / (I / b + P_large) times the pass's scale. The
 * chain's states have density I / b, the large steps' proposals density P_large (uniform), so
 * in expectation the image gets C (I / b + P_large) / (I / b + P_large) = C; where I is small
 * the large steps carry the estimate as plain Monte Carlo would (without them, P_large = 0,
 * the weight is Veach's b C / I). The current state's weights are gathered while it stays
 * current and splatted once, when it is left or at the end of the launch. */
#ifndef CLPT_INTEGRATORS_MLT_CHAIN_CL
#define CLPT_INTEGRATORS_MLT_CHAIN_CL

#include "film/splat.cl"
#include "integrators/mlt/pss_path.cl"

/* The splat of a state of contribution L and target I with expected-value weight w. */
inline float3 mlt_splat_value(__constant const MltParams* m, float3 L, float I, float w) {
  const float density = I / m->b + m->large_step;
  return density > 0.0f ? L * (w * m->splat_scale / density) : (float3)(0.0f);
}

/* Splats the current state's gathered weight. */
inline void mlt_flush(__constant const MltParams* m, MltChain* ch, __global float4* splat) {
  if (ch->weight > 0.0f && ch->luminance > 0.0f)
    film_splat(splat, ch->pixel, mlt_splat_value(m, vload3(0, ch->color), ch->luminance, ch->weight));
  ch->weight = 0.0f;
}

inline void mlt_step(const SceneView* s, __constant const RenderParams* p,
                     __constant const MltParams* m, MltChain* ch, __global PssCoord* coords,
                     u32 chain_key, __global float4* splat, u32* rays) {
  const Sampler proposal =
      pss_propose(ch, coords, m->dim_stride, m->dims, chain_key, m->large_step, m->sigma);
  const PssPath y = pss_path(s, p, &proposal, rays);
  const float a = pss_acceptance(y.target, ch->luminance);
  if (y.target > 0.0f)
    film_splat(splat, y.pixel,
               mlt_splat_value(m, y.L, y.target, a + (proposal.large_step ? 1.0f : 0.0f)));
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
    mlt_flush(m, ch, splat);
    vstore3(y.L, 0, ch->color);
    ch->luminance = y.target;
    ch->pixel = y.pixel;
    pss_accept(ch, &proposal);
  } else {
    pss_reject(ch, &proposal);
  }
}

#endif
