/* Reports sizeof/offsetof of the shared structs as the device compiler lays them out. */
#include "shared/ao_types.h"
#include "shared/aov_types.h"
#include "shared/bdpt_types.h"
#include "shared/ic_types.h"
#include "shared/indirect_types.h"
#include "shared/mlt_types.h"
#include "shared/photon_types.h"
#include "shared/render_types.h"
#include "shared/scene_types.h"
#include "shared/vcm_types.h"

__kernel void shared_layout(__global u32* out) {
  if (get_global_id(0) != 0) return;
  u32 i = 0;
#define LAYOUT_STRUCT(T) out[i++] = (u32)sizeof(T);
#define LAYOUT_FIELD(T, f) out[i++] = (u32)__builtin_offsetof(T, f);
#include "kernels/layout_fields.h"
#undef LAYOUT_STRUCT
#undef LAYOUT_FIELD
}
