/* Integer hashing for counter-based random numbers. */
#ifndef CLPT_SAMPLER_HASH_CL
#define CLPT_SAMPLER_HASH_CL

/* Chris Wellons' "lowbias32" integer hash (hash-prospector), a bijection on 32 bits. */
inline u32 hash_u32(u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* The top 24 bits as a float in [0, 1). */
inline float u32_to_unit_float(u32 x) { return (float)(x >> 8) * 0x1.0p-24f; }

#endif
