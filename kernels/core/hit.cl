/* A ray hit, as the BVH traversal (bvh/intersect.cl) reports it and the geometry layer
 * (geometry/surface.cl) turns it into a surface point. A plain type, so the layers above
 * core need not include the traversal to name it. */
#ifndef CLPT_CORE_HIT_CL
#define CLPT_CORE_HIT_CL

#include "shared/compat.h"

/* triangle indexes the leaf-order triangle array; b1 and b2 are the barycentric
 * coordinates of its vertices v[1] and v[2] (v[0] has 1 - b1 - b2). */
typedef struct Hit {
  float t;
  float b1;
  float b2;
  u32 triangle;
} Hit;

#endif
