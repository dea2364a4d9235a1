/* One Metropolis step of a chain (Metropolis et al. 1953): propose y, accept with
 * a = min(1, I(y) / I(x)), and splat both the proposal and the current state x with Veach's
 * expected values (Veach 1997 §11.5: y with weight a, x with 1 - a) combined by MIS with the
 * large steps seen as independent samples (Kelemen et al. 2002, §4.2): a large step's proposal
 * gets weight a + 1, and every splat is C / (I / b + P_large) times the pass's scale. The
 * chain's states have density I / b, the large steps' proposals density P_large (uniform), so
 * in expectation the image gets C (I / b + P_large) / (I / b + P_large) = C; where I is small
 * the large steps carry the estimate as plain Monte Carlo would (without them, P_large = 0,
 * the weight is Veach's b C / I). The current state's weights are gathered while it stays
 * current and splatted once, when it is left or at the end of the launch.
 *
 * Multiplexed MLT (CLPT_MLT_MULTIPLEXED) runs chains of one path length each, b being that
 * length's normalisation b_d; a length given n_d of the N chains splats N / n_d times as much
 * (MltDepth.chain_scale), so every length counts once whatever share of the chains it got
 * (any n_d >= 1 is unbiased; n_d near N b_d / b, which the host aims at, is what pbrt-v4's
 * MLTIntegrator does by drawing each chain's length in proportion to b_d). */
#ifndef CLPT_INTEGRATORS_MLT_CHAIN_CL
#define CLPT_INTEGRATORS_MLT_CHAIN_CL

#include "film/splat.cl"
#include "film/splat_filter.cl"
#include "integrators/mlt/large_steps.cl"
#include "integrators/mlt/mmlt_path.cl"
#include "integrators/mlt/pss_path.cl"

/* The path of a chain's vector: over bdpt's strategies for mmlt (of `depth` bounces), pt's
 * path for pssmlt (its bounces first_depth on, MltParams.first_depth but for the tile
 * weights' bootstrap paths); its target is the path's luminance times its pixel's importance
 * (all 1 for --mlt-target luminance, the bootstrap's tile weights for tile:
 * host/integrators/metropolis.h). */
static inline PssPath mlt_path(const SceneView* s, __constant const RenderParams* p,
                               const Sampler* sampler, u32 depth, u32 first_depth,
                               __global const float* importance, u32* rays) {
#ifdef CLPT_MLT_MULTIPLEXED
  PssPath path = mmlt_path(s, p, sampler, depth, rays);
#else
  PssPath path = pss_path(s, p, sampler, first_depth, rays);
#endif
  path.target *= importance[path.pixel];
  return path;
}

/* The coordinates a chain's paths read: all of the vector for pssmlt (a path of any length),
 * for mmlt those of both subpaths' streams up to the chain's path length (the rest of the
 * vector stays unread, and a rejected proposal need not look at it). */
static inline u32 mlt_chain_dims(__constant const MltParams* m, u32 depth) {
#ifdef CLPT_MLT_MULTIPLEXED
  return min(m->dims, MMLT_DIMS(depth));
#else
  return m->dims;
#endif
}

/* The splat of a state of contribution L and target I with expected-value weight w, for a
 * chain of normalisation n. */
static inline float3 mlt_splat_value(__constant const MltParams* m, MltDepth n, float3 L, float I,
                                     float w) {
  const float density = I / n.b + m->large_step;
  return density > 0.0f ? L * (w * m->splat_scale * n.chain_scale / density) : (float3)(0.0f);
}

/* A path's film position within its pixel, as two unorm16 (MltChain.frac: x low, y high). */
static inline u32 mlt_pack_frac(__constant const RenderParams* p, PssPath x) {
  const float fx = x.raster.x - (float)(x.pixel % p->width), fy = x.raster.y - (float)(x.pixel / p->width);
  return (u32)clamp(fx * 65536.0f, 0.0f, 65535.0f) | ((u32)clamp(fy * 65536.0f, 0.0f, 65535.0f) << 16);
}

/* A splat into `pixel`, or with a pixel filter (film/splat_filter.cl) around the film position
 * `frac` places in it. */
static inline void mlt_splat(__constant const RenderParams* p, __global float4* splat, u32 pixel, u32 frac,
                             float3 L) {
  if (!film_splats_through_filter(p)) {
    film_splat(splat, pixel, L);
    return;
  }
  const float2 raster = (float2)((float)(pixel % p->width) + (float)(frac & 0xffffu) * (1.0f / 65536.0f),
                                 (float)(pixel / p->width) + (float)(frac >> 16) * (1.0f / 65536.0f));
  film_splat_at(p, splat, raster, L);
}

/* Splats the current state's gathered weight. */
static inline void mlt_flush(__constant const RenderParams* p, __constant const MltParams* m, MltDepth n,
                             MltChain* ch, __global float4* splat) {
  if (ch->weight > 0.0f && ch->target > 0.0f)
    mlt_splat(p, splat, ch->pixel, ch->frac,
              mlt_splat_value(m, n, vload3(0, ch->color), ch->target, ch->weight));
  ch->weight = 0.0f;
}

static inline void mlt_step(const SceneView* s, __constant const RenderParams* p,
                            __constant const MltParams* m, MltDepth n, MltChain* ch,
                            __global PssCoord* coords, u32 chain_key,
                            __global const float* importance,
                            __global float4* splat, MltLargeSteps* large, u32* rays) {
  const Sampler proposal =
      pss_propose(ch, coords, m->dim_stride, mlt_chain_dims(m, ch->depth), chain_key,
                  m->large_step, m->sigma);
  const PssPath y = mlt_path(s, p, &proposal, ch->depth, m->first_depth, importance, rays);
  if (proposal.large_step) mlt_count_large_step(large, proposal.step_key, y.target);
  const float a = pss_acceptance(y.target, ch->target);
  if (y.target > 0.0f)
    mlt_splat(p, splat, y.pixel, mlt_pack_frac(p, y),
              mlt_splat_value(m, n, y.L, y.target, a + (proposal.large_step ? 1.0f : 0.0f)));
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
    mlt_flush(p, m, n, ch, splat);
    vstore3(y.L, 0, ch->color);
    ch->target = y.target;
    ch->pixel = y.pixel;
    ch->frac = mlt_pack_frac(p, y);
    pss_accept(ch, &proposal);
  } else {
    pss_reject(ch, &proposal);
  }
}

#endif
