/* The irradiance cache's device data (--integrator ic, docs/concepts/irradiance-caching.md):
 * a record as the record kernels write it and the lookups read it, and the parameters of the
 * cache's kernels (kernels/integrators/ic.cl). The host builds the grid over the records'
 * validity spheres (host/integrators/ic_grid.h). */
#ifndef CLPT_SHARED_IC_TYPES_H
#define CLPT_SHARED_IC_TYPES_H

#include "shared/compat.h"
#include "shared/photon_types.h"

CLPT_BEGIN_SHARED

/* One record of Ward's cache: 136 bytes. */
typedef struct IcRecord {
  float p[3];     /* where it was computed */
  float r;        /* R_i: harmonic mean distance of its hemisphere rays, clamped so that its
                   * validity radius a R_i lies within the spacing bounds; while a candidate
                   * (ic_place's output): the pixel footprint at p */
  float n[3];     /* the shading normal its hemisphere was taken around */
  u32 depth;      /* bounces before p (delta scatterings on the way from the camera) */
  float e[3];     /* indirect irradiance (RGB) */
  u32 pixel;      /* the pixel whose camera ray found p */
  float rot[9];   /* rotational gradient, one world-space vector per channel (r, g, b) */
  float trans[9]; /* translational gradient, likewise */
  float footprint;  /* the pixel footprint at p (from the candidate's r) */
  float inv_r_sum;  /* sum of 1 / r_j over all its rays so far */
  u32 rays;         /* hemisphere rays so far: e, rot and trans are their means, batch by
                     * batch (a record refines while --time leaves it a share) */
  u32 pad;
} IcRecord;

/* The cache's kernels' parameters, beside RenderParams. */
typedef struct IcParams {
  float error;          /* a (--ic-error): records with eps_i < a contribute */
  float min_spacing;    /* bounds of a record's validity radius a R_i, in pixel footprints */
  float max_spacing;
  float footprint_per_distance; /* a pixel's footprint at distance 1 along a camera path */
  float footprint_constant;     /* ... plus this (orthographic cameras) */
  u32 rays_theta;       /* M: strata of a record's hemisphere in cos^2 theta ... */
  u32 rays_phi;         /* N: ... and in phi (M N rays) */
  u32 gradients;        /* 1: lookups extrapolate with the records' gradients */
  u32 show_records;     /* 1: pixels whose camera ray placed a record render red */
  u32 record_count;     /* records in the buffer the lookups read */
  u32 level_mask;       /* bit L: the grid has records at level L */
  u32 bucket_mask;      /* buckets - 1 (a power of two) */
  float inv_cell;       /* 1 / the side of a level-0 cell (level L: 2^L times that side) */
  u32 step;             /* ic_place: pixels between grid points */
  u32 grid_w, grid_h;   /* ic_place: grid points per row and column */
  u32 first;            /* ic_record_*: the batch's first record ... */
  u32 batch;            /* ... and its record count */
  u32 capacity;         /* ic_place: candidates the candidate buffer holds ... */
  u32 grid_first;       /* ... for grid points grid_first .. grid_first + capacity - 1 */
  u32 jitter;           /* ic_place: 0 pixel centres; 1 a random point in each pixel */
  u32 gather;           /* IcGather: what a record's ray adds where it lands */
  u32 pad[2];
  PhotonLookup photons; /* how records read the global photon map (IC_GATHER_PHOTONS*) */
} IcParams;

/* What a record's hemisphere ray adds where it lands (kernels/integrators/ic/records.cl). */
enum IcGather {
  IC_GATHER_PATHS = 0,              /* NEE and pt's continuation (ic) */
  IC_GATHER_PHOTONS = 1,            /* the global photon map's estimate (ic --ic-photons) */
  IC_GATHER_PHOTONS_NO_CAUSTICS = 2 /* ... without the emission seen through delta and glossy
                                     * surfaces, a caustic map's (pm --final-gather-cache) */
};

#define IC_MAX_LEVELS 24u
/* A grid entry (kernels/spatial/sphere_grid.cl): level << IC_ENTRY_LEVEL_SHIFT | record. */
#define IC_ENTRY_LEVEL_SHIFT 27u
#define IC_ENTRY_INDEX_MASK 0x07ffffffu

CLPT_END_SHARED

#endif
