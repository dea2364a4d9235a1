/* CLPT_PREFETCH(p): a hint to fetch the cache line at p ahead of its use, for loads whose
 * address is known well before the data is needed (the accepted hit's triangle row in the
 * BVH traversal, a kd-tree node's grandchildren and the photons a kNN search keeps), and
 * CLPT_PREFETCH_WRITE(p) for a line about to be written (the splat film's pixel that a
 * light path's camera connection lands in, fetched while the shadow ray is traced).
 * clang's __builtin_prefetch, which PoCL's CPU code makes a prefetcht0 (OpenCL's own
 * prefetch() is a no-op there), where the host says the device takes it
 * (CLPT_PREFETCH_HINTS, given to PoCL's devices by cl::device_kind_options: Oclgrind stops at
 * the intrinsic); nothing elsewhere. A hint never faults, so p may point past an array. */
#ifndef CLPT_CORE_PREFETCH_CL
#define CLPT_CORE_PREFETCH_CL

#if defined(__clang__) && defined(CLPT_PREFETCH_HINTS) && CLPT_PREFETCH_HINTS
#define CLPT_PREFETCH(p) __builtin_prefetch(p)
#define CLPT_PREFETCH_WRITE(p) __builtin_prefetch(p, 1)
#else
#define CLPT_PREFETCH(p)
#define CLPT_PREFETCH_WRITE(p)
#endif

#endif
