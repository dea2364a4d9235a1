/* The fixed layout of sample dimensions along a path. 2D pairs start at even dimensions,
 * so samplers that stratify pairs jointly (stratified, Sobol) see whole pairs. */
#ifndef CLPT_SAMPLER_DIMENSIONS_H
#define CLPT_SAMPLER_DIMENSIONS_H

#define DIM_PIXEL 0u        /* 2D: position inside the pixel */
#define DIM_CAMERA_LENS 2u  /* 2D: the point on a thin lens (--aperture) */
#define DIM_BOUNCE_BASE 4u  /* first dimension of bounce 0 */
#define DIM_PER_BOUNCE 8u

/* Offsets within one bounce. */
#define DIM_LIGHT_POINT 0u  /* 2D */
#define DIM_BSDF_DIR 2u     /* 2D */
#define DIM_LIGHT_SELECT 4u /* 1D */
#define DIM_BSDF_LOBE 5u    /* 1D: which lobe of the BSDF mixture samples the direction */
#define DIM_RR 6u           /* 1D */
#define DIM_LVC_PICK 7u     /* 1D: bdpt with light vertex caching, which cached vertex */

/* Light paths (--integrator lt, kernels/integrators/lt/light_trace.cl) use the same layout:
 * the emitted ray takes the camera ray's places, and light vertex k (0: on the light) takes
 * bounce k's: its camera connection's lens point, its BSDF direction, lobe and roulette.
 * The light is chosen with bounce 0's DIM_LIGHT_SELECT. */
#define DIM_LT_EMIT_POS DIM_PIXEL       /* 2D: the point on the light */
#define DIM_LT_EMIT_DIR DIM_CAMERA_LENS /* 2D: the emitted direction */
#define DIM_LT_LENS DIM_LIGHT_POINT     /* per vertex, 2D: the lens point it connects to */

/* Extra light samples at a vertex (--light-samples) and extra branches at the first hit
 * (--branching) draw from their own streams of dimensions: stream = branch * 256 + light
 * sample index; stream 0 is the plain path. */
#define DIM_STREAM_STRIDE 0x10000u
/* BDPT's light subpath shares its camera subpath's sampler key (kernels/integrators/estimators/bdpt/),
 * with the light tracer's layout in a stream of its own. */
#define DIM_BDPT_LIGHT_STREAM 0xff00u
/* Dispersion's channel pick at bounce d of a walk (kernels/integrators/stages/walk.cl):
 * offset 0 on the camera side, 1 on the light side, of bounce d in this stream. pt's
 * branches share it (each branch alone is still unbiased). */
#define DIM_DISPERSION_STREAM 0xfe00u
#define DIM_STREAMS_PER_BRANCH 256u
/* Multiplexed MLT's choice of the bdpt strategy (kernels/integrators/mlt/mmlt_path.cl): a
 * dimension no light subpath reads (bounce 0's light vertex caching pick, light stream). */
#define DIM_MMLT_STRATEGY (DIM_BOUNCE_BASE + DIM_LVC_PICK + DIM_BDPT_LIGHT_STREAM * DIM_STREAM_STRIDE)

static inline u32 bounce_dim(u32 bounce, u32 offset) {
  return DIM_BOUNCE_BASE + bounce * DIM_PER_BOUNCE + offset;
}

static inline u32 stream_dim(u32 dimension,
                             u32 stream) { return dimension + stream * DIM_STREAM_STRIDE; }

#endif
