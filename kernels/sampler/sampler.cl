/* The sampler the integrators read: one interface, two implementations, chosen per program.
 *   float  sample_1d(const Sampler*, dimension);
 *   float2 sample_2d(const Sampler*, dimension);  -- dimensions (d, d+1) as one pair
 * Values are in [0, 1); dimensions follow sampler/dimensions.h.
 *
 *   pixel_sampler.cl  the --sampler family: a pure function of (seed, pixel, sample index,
 *                     dimension). Every program but Metropolis's.
 *   pss.cl            a Metropolis chain's primary sample vector (Kelemen et al. 2002): each
 *                     dimension is one coordinate of a vector in device memory, mutated and
 *                     restored by the chain. A program gets it by defining
 *                     CLPT_PRIMARY_SAMPLE_SPACE before its first include
 *                     (kernels/integrators/mlt.cl).
 * The path code above this layer is the same for both: the path tracer that mlt runs is
 * pt's, function for function. */
#ifndef CLPT_SAMPLER_SAMPLER_CL
#define CLPT_SAMPLER_SAMPLER_CL

/* What both include comes first: the host inlines each file once, where it is first
 * included, and knows nothing of #ifdef, so a file first reached inside the branch this
 * program leaves out would be missing from it. */
/* clang-format off: render_types.h must come first, it defines u32, which dimensions.h uses */
#include "shared/render_types.h"
/* clang-format on */
#include "sampler/dimensions.h"
#include "sampler/hash.cl"
#include "shared/mlt_types.h"

#ifdef CLPT_PRIMARY_SAMPLE_SPACE
#include "sampler/pss.cl"
#else
#include "sampler/pixel_sampler.cl"
#endif

#endif
