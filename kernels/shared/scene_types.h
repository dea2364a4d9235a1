/* Scene data as the device sees it: BVH nodes, triangles, vertices, materials, emitters. */
#ifndef CLPT_SHARED_SCENE_TYPES_H
#define CLPT_SHARED_SCENE_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* 32-byte BVH node, depth-first order: an interior node's first child follows it.
 * count > 0: leaf holding triangles [offset, offset + count) (leaf order).
 * count <= 0: interior node, offset = index of the second child, split axis = -count. */
typedef struct BvhNode {
  float bmin[3];
  i32 offset;
  float bmax[3];
  i32 count;
} BvhNode;

/* A triangle in BVH leaf order: three indices into the vertex array and its material. */
typedef struct Triangle {
  u32 v[3];
  u32 material;
} Triangle;

/* 32 bytes: position with u, normal with v. A zero normal means "use the geometric normal". */
typedef struct Vertex {
  float p[3];
  float u;
  float n[3];
  float v;
} Vertex;

enum MaterialFlags { MATERIAL_DOUBLE_SIDED = 1u, MATERIAL_EMISSIVE = 2u };

typedef struct Material {
  float base_color[4]; /* linear RGBA */
  float emission[3];   /* radiance */
  u32 flags;           /* MaterialFlags */
  float metallic;
  float roughness;
  float pad[2];
} Material;

/* One emissive triangle, with its entry of the power-proportional alias table.
 * Selection: pick slot i uniformly; keep it if u < alias_threshold, else take alias. */
typedef struct Emitter {
  u32 triangle;          /* index in leaf order */
  float pdf_select;      /* probability this emitter is chosen */
  float alias_threshold; /* alias table: probability of keeping slot i */
  u32 alias;             /* alias table: the other emitter of slot i */
} Emitter;

CLPT_END_SHARED

#endif
