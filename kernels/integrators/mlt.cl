/* Entry points of Metropolis light transport (--integrator mlt,
 * host/integrators/metropolis.cpp, docs/concepts/metropolis.md), primary-sample-space MLT
 * over pt's paths or, built with CLPT_MLT_MULTIPLEXED, multiplexed MLT over bdpt's strategies:
 *   mlt_begin      the bootstrap (starting 0): path i's target value, the fresh vector
 *                  of key i, a path of i % depths bounces for mmlt (the host estimates each
 *                  length's b from them and picks the chains' start states); a launch
 *                  traces the paths MltParams.bootstrap_first on, one per work-item;
 *                  the chains' start (starting 1): chain c starts at bootstrap path
 *                  start[c] (same key, same vector, same length, same path);
 *                  a restart (starting 2): chain c, unless start[c] is ~0, takes pick
 *                  start[c] % MLT_PICKS of chain start[c] / MLT_PICKS from its large steps
 *                  (MltLargeSteps), a state drawn from its length's pool in proportion to
 *                  the target;
 *   mlt_mutate     every chain takes MltParams.mutations steps and splats them;
 *   mlt_add_direct the direct light (pt_render's, bounces 0 and 1) into the film's sums.
 * The program reads its random numbers from the chains' vectors (sampler/pss.cl). */
#define CLPT_PRIMARY_SAMPLE_SPACE 1
#include "integrators/mlt/chain.cl"

/* The key of bootstrap path i: a fresh vector. */
static inline u32 mlt_bootstrap_key(u32 seed,
                                    u32 i) { return hash_combine(hash_u32(seed ^ 0x510e527fu), i); }

/* Both launches of a chain's beginning run one kernel, so that the program holds two copies
 * of the path (here and in mlt_mutate's steps) rather than three: a GPU compiler's time and a
 * driver's first-run build grow with every inlined copy (issue 19; dg2: docs/BENCHMARKS.md).
 * starting 0: bootstrap path i = MltParams.bootstrap_first + w, its target and pixel;
 * starting 1: chain w's first state, bootstrap path start[w] again (its key, vector, length).
 * The buffers the other launch writes are not touched. */
__kernel void mlt_begin(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __constant const MltParams* mlt, u32 starting, __global const u32* start,
                        __global const float* importance, __global float* target,
                        __global u32* pixel, __global MltChain* chains, __global PssCoord* coords,
                        __global const MltLargeSteps* large, __global u32* ray_counts) {
  const u32 w = get_global_id(0);
  if (w >= (starting ? mlt->chains : mlt->bootstrap_count)) return;
  if (starting == 2u && start[w] == 0xffffffffu) return;
  const u32 i = starting ? start[w] : mlt->bootstrap_first + w;
  const SceneView scene = SCENE_VIEW();
  MltChain ch;
  if (starting == 2u) ch = chains[w];
  const u32 depth = starting == 2u ? ch.depth : i % mlt->depths;
  const u32 dims = mlt_chain_dims(mlt, depth);
  const u32 key = starting == 2u ? large[i / MLT_PICKS].pick[i % MLT_PICKS]
                                  : mlt_bootstrap_key(mlt->seed, i);
  __global PssCoord* vector = coords + (size_t)w * mlt->chain_stride;
  Sampler sampler = pss_fresh(key, dims);
  if (starting) {
    /* A restarted chain keeps its counts, and its proposals' counter: the keys of its
     * proposals after the restart are new ones. */
    const u32 proposals = starting == 2u ? ch.proposals : 0u;
    if (starting == 1u) {
      ch.large_proposed = ch.large_accepted = ch.small_proposed = ch.small_accepted = 0u;
      ch.depth = depth;
    }
    ch.weight = 0.0f;
    ch.frac = 0u;
    pss_chain_start(&ch, vector, mlt->dim_stride, dims, key);
    ch.proposals = proposals;
    sampler = pss_current(&ch, vector, mlt->dim_stride, dims);
  }
  u32 rays = 0;
  const u32 first_depth =
      !starting && mlt->weight_rounds && (i / mlt->depths) % 2u == 0u ? 0u : mlt->first_depth;
  const PssPath x = mlt_path(&scene, params, &sampler, depth, first_depth, importance, &rays);
  const u32 pixels = params->width * params->height;
  if (starting) {
    vstore3(x.L, 0, ch.color);
    ch.target = x.target;
    ch.pixel = x.pixel;
    ch.frac = mlt_pack_frac(params, x);
    chains[w] = ch;
    atomic_add(ray_counts + w % pixels, rays);
  } else {
    target[w] = x.target;
    pixel[w] = x.pixel;
    atomic_add(ray_counts + i % pixels, rays);
  }
}

/* large[c]: chain c's pool of large steps since its length's last restart, to which this
 * launch's add (the host estimates b from them and restarts chains from the picks). */
__kernel void mlt_mutate(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                         __constant const MltParams* mlt, __global const MltDepth* depths,
                         __global const float* importance, __global MltChain* chains,
                         __global PssCoord* coords, __global float4* splat,
                         __global MltLargeSteps* large, __global u32* ray_counts) {
  const u32 c = get_global_id(0);
  if (c >= mlt->chains) return;
  const SceneView scene = SCENE_VIEW();
  MltChain ch = chains[c];
  __global PssCoord* vector = coords + (size_t)c * mlt->chain_stride;
  const u32 key = pss_chain_key(mlt->seed, mlt->chain_base + c);
  const MltDepth n = depths[ch.depth];
  MltLargeSteps ls = large[c];
  u32 rays = 0;
  for (u32 i = 0; i < mlt->mutations; ++i)
    mlt_step(&scene, params, mlt, n, &ch, vector, key, importance, splat, &ls, &rays);
  mlt_flush(params, mlt, n, &ch, splat);
  chains[c] = ch;
  large[c] = ls;
  atomic_add(ray_counts + c % (params->width * params->height), rays);
}

/* mmlt's direct light, rendered apart (--mlt-direct; host/integrators/metropolis.h): the
 * film's per-pixel sums, which the chains leave alone, become the direct light's sums over all
 * of its samples so far (pt_render's, bounces 0 and 1) times `scale`, the mutations per pixel
 * so far over those samples per pixel: the film's division by the mutations then gives their
 * mean, however few they are. The pass's direct rays go into the film's counts. */
__kernel void mlt_add_direct(__global float4* film_sum, __global u32* ray_counts,
                             __global const float4* direct_sum, __global u32* direct_rays,
                             float scale, u32 pixels) {
  const u32 i = get_global_id(0);
  if (i >= pixels) return;
  const float4 d = direct_sum[i];
  film_sum[i] = (float4)(d.xyz * scale, d.w);
  ray_counts[i] += direct_rays[i];
  direct_rays[i] = 0u;
}
