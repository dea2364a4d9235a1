/* Warp ids shared by tests/kernels/warp_test.cl and tests/warp_test.cpp (one list, so the
 * two sides cannot drift apart). */
#ifndef CLPT_TESTS_WARP_IDS_H
#define CLPT_TESTS_WARP_IDS_H
#define WARP_UNIFORM_HEMISPHERE 0
#define WARP_COSINE_HEMISPHERE 1
#define WARP_UNIFORM_SPHERE 2
#define WARP_UNIFORM_CONE 3
#define WARP_CONCENTRIC_DISK 4
#define WARP_UNIFORM_DISK 5
#define WARP_UNIFORM_TRIANGLE 6
#endif
