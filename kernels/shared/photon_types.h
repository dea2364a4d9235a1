/* Photon mapping's device data (docs/concepts/photon-mapping.md): the photon as the
 * photon-emission kernel stores it (kernels/integrators/photon/), the kd-tree node pm's
 * k-nearest-neighbour search reads (host/photon/kdtree.h builds the tree), and an SPPM
 * pixel's running statistics (kernels/integrators/sppm.cl). */
#ifndef CLPT_SHARED_PHOTON_TYPES_H
#define CLPT_SHARED_PHOTON_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* Photon.flags */
#define PHOTON_CAUSTIC 1u        /* its path was L S+ D: only delta or glossy scatterings before this hit */
#define PHOTON_BOUNCE_SHIFT 8u   /* bits 8..15: the hit's index along the path, 1 = first hit */

/* What a photon pass stores (photon_emit's `store` argument). */
#define PHOTON_STORE_CAUSTIC_ONLY 1u /* only caustic photons; paths end once they cannot make one */
#define PHOTON_STORE_SKIP_DIRECT 2u  /* not the first hit's photons (direct light is NEE's) */

/* --pm-filter: the density-estimation kernel of pm's k-nearest-neighbour estimates */
enum PhotonFilter { PHOTON_FILTER_BOX = 0, PHOTON_FILTER_CONE = 1, PHOTON_FILTER_EPANECHNIKOV = 2 };

#define PM_KNN_MAX 256u /* largest --knn: the kernels' private neighbour heap */

/* How a photon map's k-nearest-neighbour estimate reads it (--knn, --pm-max-radius,
 * --pm-filter): pm's maps, and the global map the irradiance cache's records read. */
typedef struct PhotonLookup {
  u32 knn;          /* photons per estimate (1 .. PM_KNN_MAX) */
  float max_radius; /* the search radius bound (world units) */
  u32 filter;       /* PhotonFilter */
  u32 pad;
} PhotonLookup;

/* pm's own parameters (--integrator pm, kernels/integrators/pm.cl), written by the host
 * (host/integrators/photon_mapper.cpp) beside the common RenderParams. */
typedef struct PmParams {
  PhotonLookup lookup;
  u32 final_gather; /* gather rays from the first non-delta vertex; 0: the maps there directly */
  u32 pad[3];
} PmParams;

/* 64 bytes in four 16-byte rows. */
typedef struct Photon {
  float p[3];      /* where it landed */
  u32 flags;
  float power[3];  /* flux it carries (W), already divided by the number of emitted paths */
  float pad0;
  float wi[3];     /* unit direction towards where it came from */
  float pad1;
  float n[3];      /* geometric normal of the surface, on wi's side */
  float pad2;
} Photon;

/* A point of a cell-sorted hashed grid (kernels/spatial/hash_grid.cl), the grid's points of
 * one bucket side by side: its position, its index in the points' own array, and what a
 * query tests before it reads the point's own record: the surface's normal and a small key
 * (vcm: the light vertex's depth). */
typedef struct GridPoint {
  float p[3];
  u32 index;
  float n[3];
  u32 key;
} GridPoint;

/* A node of the left-balanced, heap-ordered kd-tree (host/photon/kdtree.h: node i's
 * children are 2i + 1 and 2i + 2): its photon's position and photon_index << 2 | split axis
 * (3: a leaf). 16 bytes, read by a kernel as one float4. */
#define KD_LEAF_AXIS 3u
typedef struct KdNode {
  float pos[3];
  u32 index_axis;
} KdNode;

/* One SPPM pixel's statistics (Hachisuka and Jensen 2009) after the passes so far. */
typedef struct SppmPixel {
  float tau[3];    /* flux of the photons gathered, rescaled to the current radius */
  float n;         /* photons kept (N_i), fractional */
  float direct[3]; /* sum over passes of emission and direct light along the camera path */
  float radius;    /* current search radius; 0 until the pixel's first visible point */
} SppmPixel;

CLPT_END_SHARED

#endif
