/* Per-pass render parameters, uploaded to a small __constant buffer: what every integrator
 * reads. An integrator's own settings are in its own struct beside it (BdptParams, PmParams,
 * VcmParams, MltParams, IcParams, IndirectParams, AoParams; sppm's alpha is a kernel
 * argument). */
#ifndef CLPT_SHARED_RENDER_TYPES_H
#define CLPT_SHARED_RENDER_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

enum CameraType { CAMERA_PERSPECTIVE = 0, CAMERA_ORTHOGRAPHIC = 1 };

/* --sampler */
enum SamplerType {
  SAMPLER_INDEPENDENT = 0, /* counter-based hash (PCG-style), any sample count */
  SAMPLER_STRATIFIED = 1,  /* jittered strata per dimension pair; needs spp_total */
  SAMPLER_LHS = 2,         /* Latin hypercube (N-rooks) per dimension; needs spp_total */
  SAMPLER_SOBOL = 3        /* Owen-scrambled Sobol (0,2)-sequence, padded per dimension pair */
};

/* --direct: how direct light is estimated at each vertex */
enum DirectStrategy { DIRECT_MIS = 0, DIRECT_LIGHT = 1, DIRECT_BSDF = 2 };
/* --mis */
enum MisHeuristic { MIS_POWER = 0, MIS_BALANCE = 1 };
/* --hemisphere: how the next direction is sampled for diffuse surfaces */
enum HemisphereSampling { HEMISPHERE_BSDF = 0, HEMISPHERE_COSINE = 1, HEMISPHERE_UNIFORM = 2 };
/* --rr */
enum RussianRoulette { RR_THROUGHPUT = 0, RR_FIXED = 1 };
/* --filter: the pixel reconstruction filter, by filter importance sampling (camera/pixel_filter.cl) */
enum PixelFilter { FILTER_BOX = 0, FILTER_TENT = 1, FILTER_GAUSSIAN = 2, FILTER_BLACKMAN_HARRIS = 3 };

/* A pinhole or orthographic camera as world-space vectors. For a film point (sx, sy) in
 * [-1, 1]^2 (+y up), a perspective ray has direction forward + sx*right + sy*up from
 * origin; an orthographic ray starts at origin + sx*right + sy*up along forward.
 * A thin lens (lens_radius > 0) moves the origin over a disk of that radius in the
 * right/up plane and aims the ray at the point the pinhole ray reaches on the plane
 * focus_distance ahead (Kolb et al. 1995; pbrt's thin lens). */
typedef struct CameraData {
  float origin[4];
  float right[4];   /* perspective: tan(fov_x / 2) * camera x; orthographic: half width * x */
  float up[4];      /* perspective: tan(fov_y / 2) * camera y; orthographic: half height * y */
  float forward[4]; /* unit view direction (camera -z) */
  u32 type;         /* CameraType */
  float lens_radius;    /* thin lens: aperture radius in scene units; 0 = pinhole */
  float focus_distance; /* thin lens: distance along forward of the plane in focus */
  u32 pad;
} CameraData;

typedef struct RenderParams {
  CameraData camera;
  u32 width;
  u32 height;
  u32 max_depth;        /* bounces; 0 shows emitters only */
  u32 rr_depth;         /* Russian roulette may end paths from this bounce on */
  u32 seed;
  u32 sample_offset;    /* index of this pass's first sample in every pixel */
  u32 samples_per_pass; /* samples each pixel takes this pass */
  u32 spp_total;        /* samples per pixel of the whole render; 0 = not known in advance */
  u32 sampler;          /* SamplerType */
  u32 direct;           /* DirectStrategy */
  u32 mis;              /* MisHeuristic */
  u32 light_samples;    /* shadow rays per vertex (>= 1) */
  u32 hemisphere;       /* HemisphereSampling */
  u32 rr;               /* RussianRoulette */
  float rr_absorb;      /* absorption probability for RR_FIXED */
  u32 branching;        /* secondary rays at the first hit (>= 1; 1 = path tracing) */
  u32 filter;           /* PixelFilter of the camera samples' film positions */
  float filter_radius;  /* its radius in pixels (box 0.5: one pixel, the plain jitter) */
  u32 filter_splat;     /* 1: the filter is applied where contributions are added (integrators
                         * that splat: camera samples jitter in their pixel and every
                         * contribution is spread over the pixels whose filters reach it);
                         * 0: camera samples are drawn from it (filter importance sampling) */
  u32 texture_cones;    /* 1: camera walks carry a ray cone whose footprint picks the textures'
                         * mip level (--texture-filter trilinear); 0: level 0 everywhere */
} RenderParams;

CLPT_END_SHARED

#endif
