/* The BSDF inputs at one surface point, resolved from the material, its textures and the
 * vertex colour (kernels/material/material.cl fills it; kernels/bsdf/ evaluates it). One
 * struct for the whole glTF metallic-roughness model and the extensions clpt reads:
 *   KHR_materials_specular, KHR_materials_transmission, KHR_materials_ior.
 * Device only: the host never builds one. */
#ifndef CLPT_BSDF_BSDF_PARAMS_H
#define CLPT_BSDF_BSDF_PARAMS_H

typedef struct BsdfParams {
  float3 base_color;     /* linear RGB: factor x texture x COLOR_0 */
  float3 specular_color; /* KHR_materials_specular: specularColorFactor x texture (linear) */
  float metallic;        /* [0, 1] */
  float roughness;       /* perceptual roughness [0, 1]; GGX alpha = roughness^2 */
  float specular;        /* KHR_materials_specular: specularFactor x texture alpha; 1 = glTF core */
  float transmission;    /* KHR_materials_transmission: [0, 1] */
  float ior;             /* KHR_materials_ior: index of refraction inside the surface (1.5) */
} BsdfParams;

/* Which quantity a path carries: radiance from the camera side, or importance from the
 * light side (light tracing, BDPT light subpaths). The BSDF needs it for the adjoint of
 * refraction (no 1/eta^2 radiance scaling for importance, Veach 1997 §5.2). */
enum TransportMode { TRANSPORT_RADIANCE = 0, TRANSPORT_IMPORTANCE = 1 };

#endif
