/* Entry points of Metropolis light transport (--integrator mlt,
 * host/integrators/metropolis.cpp, docs/concepts/metropolis.md), primary-sample-space MLT
 * over pt's paths or, built with CLPT_MLT_MULTIPLEXED, multiplexed MLT over bdpt's strategies:
 *   mlt_bootstrap  path i of the bootstrap: the target value of the fresh vector of key i,
 *                  a path of i % depths bounces for mmlt (the host estimates each length's
 *                  b from them and picks the chains' start states); a launch traces the
 *                  paths MltParams.bootstrap_first on, one per work-item;
 *   mlt_start      chain c starts at bootstrap path start[c] (same key, same vector, same
 *                  length, same path);
 *   mlt_mutate     every chain takes MltParams.mutations steps and splats them.
 * The program reads its random numbers from the chains' vectors (sampler/pss.cl). */
#define CLPT_PRIMARY_SAMPLE_SPACE 1
#include "integrators/mlt/chain.cl"

/* The key of bootstrap path i: a fresh vector. */
static inline u32 mlt_bootstrap_key(u32 seed,
                                    u32 i) { return hash_combine(hash_u32(seed ^ 0x510e527fu), i); }

__kernel void mlt_bootstrap(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                            __constant const MltParams* mlt, __global const float* importance,
                            __global float* target, __global u32* pixel, __global u32* ray_counts) {
  const u32 j = get_global_id(0);
  if (j >= mlt->bootstrap_count) return;
  const u32 i = mlt->bootstrap_first + j;
  const SceneView scene = SCENE_VIEW();
  const u32 depth = i % mlt->depths;
  const Sampler sampler = pss_fresh(mlt_bootstrap_key(mlt->seed, i), mlt_chain_dims(mlt, depth));
  u32 rays = 0;
  const PssPath path = mlt_path(&scene, params, &sampler, depth, importance, &rays);
  target[j] = path.target;
  pixel[j] = path.pixel;
  atomic_add(ray_counts + i % (params->width * params->height), rays);
}

__kernel void mlt_start(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __constant const MltParams* mlt, __global const u32* start,
                        __global const float* importance, __global MltChain* chains,
                        __global PssCoord* coords,
                        __global u32* ray_counts) {
  const u32 c = get_global_id(0);
  if (c >= mlt->chains) return;
  const SceneView scene = SCENE_VIEW();
  __global PssCoord* vector = coords + (size_t)c * mlt->chain_stride;
  MltChain ch;
  ch.weight = 0.0f;
  ch.large_proposed = ch.large_accepted = ch.small_proposed = ch.small_accepted = 0u;
  ch.depth = start[c] % mlt->depths;
  ch.frac = 0u;
  const u32 dims = mlt_chain_dims(mlt, ch.depth);
  pss_chain_start(&ch, vector, mlt->dim_stride, dims, mlt_bootstrap_key(mlt->seed, start[c]));
  const Sampler sampler = pss_current(&ch, vector, mlt->dim_stride, dims);
  u32 rays = 0;
  const PssPath x = mlt_path(&scene, params, &sampler, ch.depth, importance, &rays);
  vstore3(x.L, 0, ch.color);
  ch.target = x.target;
  ch.pixel = x.pixel;
  ch.frac = mlt_pack_frac(params, x);
  chains[c] = ch;
  atomic_add(ray_counts + c % (params->width * params->height), rays);
}

__kernel void mlt_mutate(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                         __constant const MltParams* mlt, __global const MltDepth* depths,
                         __global const float* importance, __global MltChain* chains,
                         __global PssCoord* coords, __global float4* splat,
                         __global u32* ray_counts) {
  const u32 c = get_global_id(0);
  if (c >= mlt->chains) return;
  const SceneView scene = SCENE_VIEW();
  MltChain ch = chains[c];
  __global PssCoord* vector = coords + (size_t)c * mlt->chain_stride;
  const u32 key = pss_chain_key(mlt->seed, mlt->chain_base + c);
  const MltDepth n = depths[ch.depth];
  u32 rays = 0;
  for (u32 i = 0; i < mlt->mutations; ++i) mlt_step(&scene, params, mlt, n, &ch, vector, key, importance, splat, &rays);
  mlt_flush(params, mlt, n, &ch, splat);
  chains[c] = ch;
  atomic_add(ray_counts + c % (params->width * params->height), rays);
}
