/* Scene data as the device sees it: BVH nodes, triangles, vertices, materials, textures,
 * lights and scene-wide scalars. */
#ifndef CLPT_SHARED_SCENE_TYPES_H
#define CLPT_SHARED_SCENE_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* 128-byte node of the 4-wide BVH the kernels traverse, collapsed from the binary build
 * (host/bvh/bvh.h's BvhNode, which only the host sees): the boxes of up to four children, one array per bound and axis (child i's
 * box is lane i of the six), and per child: child[i] >= 0 the index of its node; child[i] < 0
 * a leaf of count[i] triangles from ~child[i] (leaf order). An empty slot has an empty box
 * (bmin +inf, bmax -inf), child -1 and count 0, so a ray with a NaN origin, which enters any
 * box, reads nothing there. nodes[0] is the root; an empty scene's has four empty slots. */
typedef struct BvhNode4 {
  float bmin_x[4];
  float bmin_y[4];
  float bmin_z[4];
  float bmax_x[4];
  float bmax_y[4];
  float bmax_z[4];
  i32 child[4];
  u32 count[4];
} BvhNode4;

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

/* Optional per-vertex attributes, one per Vertex, uploaded only when some primitive of the
 * scene has one of them (SceneInfo.flags & SCENE_VERTEX_EXTRA); otherwise the buffer holds one
 * dummy element and the kernel does not read it. */
typedef struct VertexExtra {
  float tangent[4]; /* xyz unit tangent (world space), w = bitangent sign; all zero: none */
  float color[4];   /* COLOR_0, linear RGBA; (1,1,1,1) when the primitive has none */
  float uv1[2];     /* TEXCOORD_1 */
  float pad[2];
} VertexExtra;

/* A decoded RGBA image: width x height texels starting at word `offset` of the texel buffer,
 * row 0 at the top (v = 0). 8 bits a channel: a texel is one u32 with R in the low byte;
 * TEXTURE_WIDE (a 16-bit normal map, host/scene/gltf/materials.cpp): 16 bits a channel, a
 * texel is two u32, R | G << 16 then B | A << 16. */
enum TextureFlags {
  TEXTURE_WRAP_S_MASK = 3u, /* bits 0-1: TextureWrap for u */
  TEXTURE_WRAP_T_SHIFT = 2u, /* bits 2-3: TextureWrap for v */
  TEXTURE_NEAREST = 16u,     /* magnification filter NEAREST (default: bilinear) */
  TEXTURE_WIDE = 32u,        /* 16 bits a channel, two words a texel (above) */
  TEXTURE_LEVELS_SHIFT = 8u  /* bits 8-12: mip levels, level 0 included (1: none); level k + 1
                              * is max(1, w / 2) x max(1, h / 2) of level k's w x h, its texels
                              * right after level k's (host/render/mipmaps.h) */
};
enum TextureWrap { WRAP_REPEAT = 0u, WRAP_CLAMP = 1u, WRAP_MIRROR = 2u };

typedef struct Texture {
  u32 offset; /* first texel in the texel buffer */
  u32 width;
  u32 height;
  u32 flags;  /* TextureFlags */
} Texture;

/* Where a material reads one of its textures. uv' = (m[0] u + m[1] v + m[2],
 * m[3] u + m[4] v + m[5]): KHR_texture_transform folded into a 2x3 matrix (identity without). */
enum TextureSlotId {
  TEX_BASE_COLOR = 0,         /* sRGB; alpha is the material alpha */
  TEX_METALLIC_ROUGHNESS = 1, /* linear; B metallic, G roughness */
  TEX_NORMAL = 2,             /* linear tangent-space normal map */
  TEX_EMISSIVE = 3,           /* sRGB */
  TEX_TRANSMISSION = 4,       /* linear; R */
  TEX_SPECULAR = 5,           /* linear; A specularFactor */
  TEX_SPECULAR_COLOR = 6,     /* sRGB; RGB specularColorFactor */
  TEX_CLEARCOAT = 7,          /* linear; R clearcoatFactor */
  TEX_CLEARCOAT_ROUGHNESS = 8, /* linear; G clearcoatRoughnessFactor */
  TEX_IRIDESCENCE = 9,        /* linear; R iridescenceFactor */
  TEX_IRIDESCENCE_THICKNESS = 10, /* linear; G: mix(thickness minimum, maximum, G) */
  TEX_DIFFUSE_TRANSMISSION = 11,  /* linear; A diffuseTransmissionFactor */
  TEX_DIFFUSE_TRANSMISSION_COLOR = 12, /* sRGB; RGB diffuseTransmissionColorFactor */
  TEX_SHEEN_COLOR = 13,       /* sRGB; RGB sheenColorFactor */
  TEX_SHEEN_ROUGHNESS = 14,   /* linear; A sheenRoughnessFactor */
  TEX_ANISOTROPY = 15,        /* linear; RG direction in tangent space (x 2 - 1), B strength */
  TEX_CLEARCOAT_NORMAL = 16,  /* linear tangent-space normal map of the clearcoat */
  TEX_SLOT_COUNT = 17
};

typedef struct TextureSlot {
  i32 texture;  /* index into the textures, -1: no texture */
  u32 texcoord; /* 0: TEXCOORD_0, 1: TEXCOORD_1 */
  float m[6];   /* texture transform */
} TextureSlot;

enum MaterialFlags {
  MATERIAL_DOUBLE_SIDED = 1u,
  MATERIAL_EMISSIVE = 2u,
  MATERIAL_ALPHA_MASK = 4u,  /* alphaMode MASK: alpha < alpha_cutoff is a hole */
  MATERIAL_ALPHA_BLEND = 8u, /* alphaMode BLEND: stochastic transparency with probability 1 - alpha */
  MATERIAL_VOLUME = 16u,     /* KHR_materials_volume attenuation inside (closed meshes) */
  MATERIAL_ANISOTROPIC = 32u, /* KHR_materials_anisotropy with a strength > 0 */
  MATERIAL_TEXTURED = 64u,    /* a slot other than the emissive one has a texture (the
                               * footprint of a lookup matters) */
  MATERIAL_PLAIN = 128u       /* no texture in any slot and no layer (clearcoat, iridescence,
                               * diffuse transmission, sheen, anisotropy): the factors alone
                               * (material/material.cl's material_resolve_plain) */
};

typedef struct Material {
  float base_color[4]; /* linear RGBA (factor) */
  float emission[3];   /* radiance: emissiveFactor x emissive_strength (x texture) */
  u32 flags;           /* MaterialFlags */
  float metallic;
  float roughness;
  float alpha_cutoff;  /* alphaMode MASK */
  float ior;           /* KHR_materials_ior (1.5) */
  float transmission;  /* KHR_materials_transmission factor (0) */
  float specular;      /* KHR_materials_specular specularFactor (1) */
  float normal_scale;  /* normalTexture.scale (1) */
  float attenuation_distance; /* KHR_materials_volume (infinity: none) */
  float clearcoat;            /* KHR_materials_clearcoat clearcoatFactor (0) */
  float clearcoat_roughness;  /* clearcoatRoughnessFactor (0) */
  float iridescence;          /* KHR_materials_iridescence iridescenceFactor (0) */
  float iridescence_ior;      /* iridescenceIor (1.3): the film's index */
  float iridescence_thickness_min; /* iridescenceThicknessMinimum, nm (100) */
  float iridescence_thickness_max; /* iridescenceThicknessMaximum, nm (400) */
  float diffuse_transmission; /* KHR_materials_diffuse_transmission factor (0) */
  float sheen_roughness;      /* KHR_materials_sheen sheenRoughnessFactor (0) */
  float specular_color[4];    /* KHR_materials_specular specularColorFactor (1,1,1), w unused */
  float attenuation_color[4]; /* KHR_materials_volume (1,1,1), w unused */
  float diffuse_transmission_color[4]; /* diffuseTransmissionColorFactor (1,1,1), w unused */
  float sheen_color[4];       /* KHR_materials_sheen sheenColorFactor (0,0,0), w unused */
  float anisotropy[4];        /* KHR_materials_anisotropy: anisotropyStrength (0), then cos and
                               * sin of anisotropyRotation (1, 0), w unused */
  float clearcoat_normal_scale; /* clearcoatNormalTexture.scale (1) */
  float dispersion;             /* KHR_materials_dispersion: 20 / Abbe number (0: none) */
  u32 pad[2];
  TextureSlot tex[TEX_SLOT_COUNT];
} Material;

/* The lights of one power-proportional selection distribution: emissive triangles, glTF
 * punctual lights and the environment. Selection: pick slot i uniformly; keep it if
 * u < alias_threshold, else take alias. */
enum LightType {
  LIGHT_TRIANGLE = 0,
  LIGHT_POINT = 1,
  LIGHT_SPOT = 2,
  LIGHT_DIRECTIONAL = 3,
  LIGHT_ENVIRONMENT = 4
};

typedef struct Light {
  u32 type;              /* LightType */
  u32 triangle;          /* LIGHT_TRIANGLE: index in leaf order */
  float pdf_select;      /* probability this light is chosen */
  float alias_threshold; /* alias table: probability of keeping slot i */
  u32 alias;             /* alias table: the other light of slot i */
  u32 pad[3];
  float position[4];     /* point, spot: world position */
  float direction[4];    /* spot, directional: unit direction the light travels */
  float intensity[4];    /* point, spot: radiant intensity (W/sr); directional: irradiance
                          * (W/m^2): the glTF intensity times the colour (README "Lights") */
  float cos_outer;       /* spot: cosine of the outer cone angle */
  float cos_inner;       /* spot: cosine of the inner cone angle */
  float pad2[2];
} Light;

enum SceneFlags {
  SCENE_VERTEX_EXTRA = 1u,
  SCENE_DELTA_LIGHTS = 2u, /* some light is a point, spot or directional light */
  SCENE_ALPHA = 4u         /* some material has alphaMode MASK or BLEND */
};

/* Scene-wide scalars, one struct in a small buffer. */
typedef struct SceneInfo {
  u32 num_lights;
  u32 flags;           /* SceneFlags */
  u32 env_light;       /* index of the environment in the lights, or ~0u */
  u32 num_textures;
  float bounds_center[4];
  float bounds_radius; /* radius of the bounding sphere of the geometry */
  u32 env_width;       /* environment map, equirectangular; 0 x 0: constant background */
  u32 env_height;
  float env_rotation;  /* radians about +y */
  float background[4]; /* constant environment radiance when env_width is 0 (--background) */
  float env_scale;     /* multiplies the map's texels (--env-scale) */
  float pad[3];
} SceneInfo;

CLPT_END_SHARED

#endif
