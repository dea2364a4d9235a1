/* The fixed layout of sample dimensions along a path. */
#ifndef CLPT_SAMPLER_DIMENSIONS_H
#define CLPT_SAMPLER_DIMENSIONS_H

#define DIM_PIXEL 0u         /* 2D: position inside the pixel */
#define DIM_CAMERA_LENS 2u   /* 2D: reserved for thin-lens cameras */
#define DIM_BOUNCE_BASE 4u   /* first dimension of bounce 0 */
#define DIM_PER_BOUNCE 8u

/* Offsets within one bounce. */
#define DIM_LIGHT_SELECT 0u  /* 1D */
#define DIM_LIGHT_POINT 1u   /* 2D */
#define DIM_BSDF_LOBE 3u     /* 1D, reserved for layered BSDFs */
#define DIM_BSDF_DIR 4u      /* 2D */
#define DIM_RR 6u            /* 1D */

inline u32 bounce_dim(u32 bounce, u32 offset) {
  return DIM_BOUNCE_BASE + bounce * DIM_PER_BOUNCE + offset;
}

#endif
