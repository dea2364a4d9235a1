/* BVH limits shared by the host builder and the device traversal. */
#ifndef CLPT_SHARED_BVH_CONSTANTS_H
#define CLPT_SHARED_BVH_CONSTANTS_H

/* Maximum number of levels of a BVH (the root is level 1). The builder never exceeds it;
 * the traversal kernels keep a private stack of this many node indices, which is enough
 * because at most one entry is pushed per level below the root. */
#define CLPT_BVH_MAX_DEPTH 64

/* The 4-wide BVH collapsed from it has at most half as many levels (every wide node's inner
 * children lie at least two binary levels below it), and a traversal leaves at most three
 * entries on its stack per level. */
#define CLPT_BVH4_STACK (3 * (CLPT_BVH_MAX_DEPTH / 2) + 1)

#endif
