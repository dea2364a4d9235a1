/* What the light interface hands back (kernels/light/light.cl):
 *   LightSample    light_illuminate's answer for a shading point (next-event estimation),
 *   LightEmission  light_emit's answer: a ray leaving a light (light tracing, issue 5).
 * Densities say their measure: pdf_w per steradian, pdf_a per unit area. */
#ifndef CLPT_LIGHT_LIGHT_TYPES_CL
#define CLPT_LIGHT_LIGHT_TYPES_CL

typedef struct LightSample {
  float3 p;      /* point on the light; for directional and environment lights, org + wi */
  float3 wi;     /* unit direction from the shading point towards the light */
  float dist;    /* distance to p; INFINITY for directional and environment lights */
  float3 n;      /* area lights: the light's geometric normal at p (either side); else 0 */
  float3 Le;     /* arriving radiance, or for a delta light the irradiance-like I / d^2 (point,
                  * spot) or E (directional): the contribution is f * Le / pdf_w either way */
  float pdf_w;   /* solid-angle density at the shading point including the light's selection
                  * probability; for delta lights the selection probability alone. 0: invalid */
  int is_delta;  /* point, spot, directional: no BSDF sample can find it (no MIS weight) */
  u32 light;     /* index of the chosen light in the light table */
} LightSample;

/* The invalid sample at shading point p (pdf_w 0): where every illuminate starts. */
static inline LightSample light_sample_none(float3 p) {
  LightSample ls;
  ls.p = p;
  ls.wi = (float3)(0.0f, 0.0f, 1.0f);
  ls.dist = 0.0f;
  ls.n = (float3)(0.0f);
  ls.Le = (float3)(0.0f);
  ls.pdf_w = 0.0f;
  ls.is_delta = 0;
  ls.light = 0u;
  return ls;
}

typedef struct LightEmission {
  float3 p;        /* ray origin: on the light, or on a disk of the scene's bounding radius
                    * for directional and environment lights */
  float3 dir;      /* unit direction the light travels */
  float3 Le;       /* emitted radiance along dir (area, environment), intensity (point, spot)
                    * or irradiance (directional) */
  float pdf_a;     /* density of p per unit area; 1 for point and spot (a delta position) */
  float pdf_w;     /* density of dir per steradian; 1 for directional (a delta direction) */
  float pdf_select;/* probability this light was chosen */
  float cos_light; /* |cos| between dir and the emitting surface's normal (area), else 1 */
  int is_delta_pos;
  int is_delta_dir;
  u32 light;       /* index of the chosen light in the light table */
} LightEmission;

#endif
