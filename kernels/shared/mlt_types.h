/* Metropolis light transport's device data (docs/concepts/metropolis.md): the parameters of
 * one launch, the normalisation per path length, a chain's state between launches, and one
 * coordinate of a chain's primary sample vector (kernels/sampler/pss.cl updates it lazily). */
#ifndef CLPT_SHARED_MLT_TYPES_H
#define CLPT_SHARED_MLT_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* Coordinates of a path tracer's primary sample vector at --max-depth D: the camera's four
 * dimensions and DIM_PER_BOUNCE for each of the bounces 0 to D (kernels/sampler/dimensions.h). */
#define PSS_DIMS(max_depth) (4u + 8u * ((max_depth) + 1u))
/* ... and of multiplexed MLT's: the camera and the light subpath's streams interleaved, each
 * laid out as a path tracer's (kernels/sampler/pss.cl). */
#define MMLT_DIMS(max_depth) (2u * PSS_DIMS(max_depth))

/* One coordinate of a chain's vector, with what a rejected proposal restores (pbrt-v4's
 * MLTSampler::PrimarySample). `modified` is the chain iteration the value belongs to. */
typedef struct PssCoord {
  float value;
  u32 modified;
  float backup;
  u32 backup_modified;
} PssCoord;

/* What one Metropolis launch needs besides RenderParams. */
typedef struct MltParams {
  u32 chains;        /* chains in flight (work-items of mlt_begin's start and mlt_mutate) */
  u32 mutations;     /* proposals per chain in this launch */
  u32 dims;          /* coordinates of a chain's vector */
  u32 dim_stride;    /* chain c's coordinate d is coords[c * chain_stride + d * dim_stride]: */
  u32 chain_stride;  /*   GPUs (chains, 1), so a warp's reads of one dimension coalesce; CPUs
                          (1, dims), so one chain's vector is one run of cache lines */
  u32 bootstrap;     /* paths of the bootstrap, all path lengths together */
  u32 depths;        /* path lengths the chains sample: 1 (pssmlt: every length in one chain)
                        or max_depth + 1 (mmlt: bootstrap path i and its chain have i % depths
                        bounces) */
  float large_step;  /* probability that a proposal is a large step (a fresh uniform vector) */
  float sigma;       /* small steps: standard deviation of the Gaussian perturbation */
  float splat_scale; /* this pass's normalisation: pixels * spp / (chains * mutations) */
  u32 seed;
  u32 chain_base;    /* the first chain's index among every device's chains: its mutations'
                        random numbers are keyed by chain_base + c (one device: 0) */
  u32 bootstrap_first; /* this bootstrap launch's paths: bootstrap_first to         */
  u32 bootstrap_count; /*   bootstrap_first + bootstrap_count - 1 (the devices share them) */
  u32 first_depth;   /* pssmlt: the shortest depth (bounces) its paths count, 2 where the direct
                        light is rendered apart (--mlt-direct), else 0; mmlt gives the shorter
                        lengths no chains instead */
  u32 weight_rounds; /* 1: the tile target's bootstrap, whose even rounds of paths
                        ((i / depths) % 2 == 0) estimate the image for the tile weights: those
                        count every depth (the weights follow the whole image) */
} MltParams;

/* What the chains of one path length (all chains, for pssmlt) splat with. */
typedef struct MltDepth {
  float b;           /* the normalisation: the mean target of the paths of this length (mmlt)
                        or of all paths (pssmlt), from the bootstrap and, after the chains'
                        last restart, from the pool of large steps they restarted from
                        (MltLargeSteps) */
  float chain_scale; /* all chains / the chains of this length: makes up for the share of the
                        chains this length was given */
} MltDepth;

/* What a chain's large steps have proposed since its length's chains last restarted: fresh
 * uniform vectors, independent of the chain, so their targets are samples of b_d as the
 * bootstrap's paths are, and a pool to restart chains from (host/integrators/metropolis.h).
 * Each pick is one of them drawn in proportion to its target (MLT_PICKS independent weighted
 * reservoirs of one), the states restarts from this chain's share of the pool take. The sum
 * is compensated (Kahan): a chain may propose hundreds of thousands between restarts.
 * 32 bytes. */
#define MLT_PICKS 4u
typedef struct MltLargeSteps {
  float sum;          /* the targets' sum */
  float compensation; /* what the float sum lost (Kahan's c) */
  float sum_sq;       /* their squares' sum, for b's standard error */
  u32 count;          /* large steps proposed */
  u32 pick[MLT_PICKS]; /* the picked proposals' keys (a vector: sampler/pss.cl's pss_fresh) */
} MltLargeSteps;

/* A chain between launches: its current state's contribution, the lazily updated vector's
 * counters and acceptance counts. 64 bytes. */
typedef struct MltChain {
  float color[3];     /* the current path's contribution C */
  float target;       /* its target value I: luminance(C), times the pixel's importance
                         (--mlt-target tile; host/integrators/metropolis.h) */
  u32 pixel;          /* the pixel its film position falls in */
  float weight;       /* expected-value weight gathered while current, not splatted yet */
  u32 iteration;      /* iterations accepted so far, plus one */
  u32 last_large;     /* iteration of the last accepted large step (1: the start state) */
  u32 large_key;      /* key of that large step's uniform values */
  u32 proposals;      /* proposals so far: the counter of the chain's random numbers */
  u32 large_proposed;
  u32 large_accepted;
  u32 small_proposed;
  u32 small_accepted;
  u32 depth;          /* mmlt: the bounces of every path of this chain (pssmlt: 0) */
  u32 frac;           /* its film position within the pixel, two unorm16 (x low, y high), for a
                         splat through the pixel filter */
} MltChain;

CLPT_END_SHARED

#endif
