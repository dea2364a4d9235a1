/* A photon as the photon-emission kernel stores it (kernels/integrators/photon/) and the
 * photon maps read it: 64 bytes in four 16-byte rows. */
#ifndef CLPT_SHARED_PHOTON_TYPES_H
#define CLPT_SHARED_PHOTON_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* Photon.flags */
#define PHOTON_CAUSTIC 1u        /* its path was L S+ D: only delta scatterings before this hit */
#define PHOTON_BOUNCE_SHIFT 8u   /* bits 8..15: the hit's index along the path, 1 = first hit */

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

CLPT_END_SHARED

#endif
