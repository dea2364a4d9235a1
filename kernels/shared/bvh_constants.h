/* BVH limits shared by the host builder and the device traversal. */
#ifndef CLPT_SHARED_BVH_CONSTANTS_H
#define CLPT_SHARED_BVH_CONSTANTS_H

/* Maximum number of levels of a BVH (the root is level 1). The builder never exceeds it;
 * the traversal kernels keep a private stack of this many node indices, which is enough
 * because at most one entry is pushed per level below the root. */
#define CLPT_BVH_MAX_DEPTH 64

#endif
