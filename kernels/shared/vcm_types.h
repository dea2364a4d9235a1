/* Vertex connection and merging's own parameters (--integrator vcm, kernels/integrators/vcm.cl,
 * docs/concepts/vcm.md), written by the host (host/integrators/vcm.cpp) for each tile of each
 * pass beside the common RenderParams. */
#ifndef CLPT_SHARED_VCM_TYPES_H
#define CLPT_SHARED_VCM_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* --vcm-mode: which techniques of the one estimator run (SmallVCM's modes). */
enum VcmMode {
  VCM_MODE_VCM = 0, /* connections and merging, all MIS-weighted */
  VCM_MODE_BPT = 1, /* connections only: bidirectional path tracing (bdpt's weights) */
  VCM_MODE_PPM = 2, /* merging only, at the first non-delta camera vertex: photon mapping */
  VCM_MODE_LT = 3,  /* light subpaths connected to the camera, unweighted: light tracing */
  VCM_MODE_PT = 4   /* camera subpaths with next-event estimation: path tracing */
};

/* The two techniques each mode runs: one rule for the host's launches and the kernels. */
static inline int vcm_mode_merges(u32 mode) { return mode == VCM_MODE_VCM || mode == VCM_MODE_PPM; }
static inline int vcm_mode_connects(u32 mode) { return mode == VCM_MODE_VCM || mode == VCM_MODE_BPT; }

typedef struct VcmParams {
  u32 mode;               /* VcmMode */
  float radius;           /* this pass's merge radius r */
  float mis_vm;           /* StrategyMis.vm = mis(eta), eta = pi r^2 light_paths; 0 without merging */
  float mis_vc;           /* StrategyMis.vc = mis(1 / eta); 0 without connections */
  float vm_normalization; /* 1 / eta: a merge's density kernel over the light paths */
  float inv_cell;         /* the light vertex grid's cells are 2r wide */
  u32 mask;               /* its buckets - 1 */
  u32 light_paths;        /* light subpaths of the tile, light_per_pixel per pixel (N_merge: each
                           * camera path merges with all) */
  u32 light_vertex_capacity; /* light vertices stored per light subpath */
  u32 lvc;                /* --bdpt-lvc: connections per camera vertex to random cached light
                           * vertices (light vertex caching, as bdpt's); 0: to its own subpath's */
  u32 pixel_radius;       /* 1: each pixel merges with its own radius (--vcm-shrink pixel), kept
                           * per pixel as (r, N) and shrunk as sppm's by the merges its first
                           * merging vertex finds; radius, mis_vm and mis_vc are then only the
                           * light subpaths' reference and the grid's cell size */
  float alpha;            /* --vcm-alpha, the per-pixel shrink's fraction of merges kept */
  float eta_per_r2;       /* pi light_paths: a pixel's eta is this times its r^2 */
  u32 merge_first;        /* 1: merging at the first non-delta camera vertex only (--vcm-merge
                           * first), 0: at every one (Georgiev 2012) */
  u32 light_per_pixel;    /* --vcm-light-paths: light subpaths per pixel and pass; a camera
                           * subpath connects to the first, merges with all, and light
                           * tracing (t = 1) takes them all */
  u32 light_sample;       /* the sample index a pixel's first light subpath of the pass draws
                           * from (its j-th: light_sample + j; the light subpaths' own stream of
                           * numbers). The pass's sample index times light_per_pixel, or with
                           * --vcm-light-paths auto, whose K changes after the pilot, the light
                           * subpaths the passes before traced per pixel */
} VcmParams;

CLPT_END_SHARED

#endif
