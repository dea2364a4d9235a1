/* The BSDF inputs at one surface point, resolved from the material, its textures and the
 * vertex colour (kernels/material/material.cl fills it; kernels/bsdf/ evaluates it). One
 * struct for the whole glTF metallic-roughness model and the extensions clpt reads:
 *   KHR_materials_specular, KHR_materials_transmission, KHR_materials_ior,
 *   KHR_materials_clearcoat, KHR_materials_iridescence, KHR_materials_diffuse_transmission,
 *   KHR_materials_sheen, KHR_materials_anisotropy.
 * Device only: the host never builds one. */
#ifndef CLPT_BSDF_BSDF_PARAMS_H
#define CLPT_BSDF_BSDF_PARAMS_H

typedef struct BsdfParams {
  float3 base_color;     /* linear RGB: factor x texture x COLOR_0 */
  float3 specular_color; /* KHR_materials_specular: specularColorFactor x texture (linear) */
  float3 diffuse_transmission_color; /* KHR_materials_diffuse_transmission: colour factor x
                                      * texture RGB (linear), [0, 1] */
  float metallic;        /* [0, 1] */
  float roughness;       /* perceptual roughness [0, 1]; GGX alpha = roughness^2 */
  float specular;        /* KHR_materials_specular: specularFactor x texture alpha; 1 = glTF core */
  float transmission;    /* KHR_materials_transmission: [0, 1] */
  float ior;             /* KHR_materials_ior: index of refraction inside the surface (1.5); with
                          * a dispersion, n_d until a walk picks its wavelength (walk_disperse) */
  float dispersion;      /* KHR_materials_dispersion: 20 / Abbe number where the surface
                          * transmits (transmission > 0), else 0 */
  float clearcoat;       /* KHR_materials_clearcoat: clearcoatFactor x texture R, [0, 1] (0) */
  float clearcoat_roughness; /* clearcoatRoughnessFactor x texture G (perceptual) */
  float3 clearcoat_n;    /* the clearcoat's normal, world space, unit, on the front face's side:
                          * clearcoatNormalTexture, else the interpolated normal (the base's
                          * normal map does not reach the coat); where it equals the shading
                          * normal bit for bit the coat shares the base's frame */
  float iridescence;     /* KHR_materials_iridescence: iridescenceFactor x texture R, [0, 1] (0) */
  float iridescence_ior; /* the film's index of refraction (1.3) */
  float iridescence_thickness; /* nm: mix(minimum, maximum, thickness texture G) */
  float diffuse_transmission; /* KHR_materials_diffuse_transmission: factor x texture A, [0, 1] */
  float3 sheen_color;    /* KHR_materials_sheen: sheenColorFactor x texture RGB (linear), [0, 1];
                          * 0: no sheen */
  float sheen_roughness; /* sheenRoughnessFactor x texture A */
  float3 anisotropy_t;   /* KHR_materials_anisotropy: the direction of the wider alpha, world
                          * space, unit, in the shading normal's tangent plane (where
                          * anisotropy > 0); bsdf_frame takes it as the local x axis */
  float anisotropy;      /* anisotropyStrength x texture B, [0, 1]; 0: isotropic */
} BsdfParams;

/* The clearcoat inputs are rounded to 16-bit unorm steps (1 / 65535) when resolved, so that
 * a PathVertex stores them exactly in one word (kernels/shared/bdpt_types.h). */
static inline float bsdf_unorm16(float x) { return rint(clamp(x, 0.0f,
                                 1.0f) * 65535.0f) * (1.0f / 65535.0f); }
static inline uint bsdf_unorm16_bits(float x) { return (uint)rint(clamp(x, 0.0f,
                                     1.0f) * 65535.0f); }

/* The sheen's inputs are rounded to 8-bit unorm steps (1 / 255, a texture's own precision),
 * so that a PathVertex stores colour and roughness exactly in one word. */
static inline float bsdf_unorm8(float x) { return rint(clamp(x, 0.0f, 1.0f) * 255.0f) * (1.0f / 255.0f); }
static inline uint bsdf_unorm8_bits(float x) { return (uint)rint(clamp(x, 0.0f, 1.0f) * 255.0f); }

/* Which quantity a path carries: radiance from the camera side, or importance from the
 * light side (light tracing, BDPT light subpaths). The BSDF needs it for the adjoint of
 * refraction (no 1/eta^2 radiance scaling for importance, Veach 1997 §5.2). */
enum TransportMode { TRANSPORT_RADIANCE = 0, TRANSPORT_IMPORTANCE = 1 };

#endif
