/* Russian roulette (--rr, --rr-depth), the same for every path of every integrator: a path
 * whose BSDF weights so far multiply to `walk` goes on with this probability and divides its
 * throughput by it. throughput: max component of walk, capped at 1; fixed:ALPHA: 1 - ALPHA. */
#ifndef CLPT_INTEGRATORS_RUSSIAN_ROULETTE_CL
#define CLPT_INTEGRATORS_RUSSIAN_ROULETTE_CL

#include "core/math.cl"
#include "shared/render_types.h"

static inline float rr_survival(__constant const RenderParams* p, float3 walk) {
  return p->rr == RR_FIXED ? 1.0f - p->rr_absorb : fmin(1.0f, max_component(walk));
}

#endif
