// The conformance matrix's scenes (tests/conformance_matrix_test.cpp): one object of a given
// material class on a stage lit by one light of a given kind, small enough that a pt
// reference and a handful of batches of any integrator take seconds.
//
// Closed stages (area lights, point, spot): a 1 m room [0,1] x [0,1] x [-1,0], open towards
// the camera at z = 0, walls Lambertian (left reddish, right greenish, the rest grey). Open
// stages (directional, environment): only the floor and the back wall, so the light reaches
// in. The object is a sphere of radius 0.2 resting on the floor at (0.5, 0.2, -0.5), or a
// material sample that needs UVs (normal map, alpha, emissive texture) on the same sphere
// with a latitude-longitude UV mapping.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt::test {

enum class StageMaterial {
  Lambert,          // white-ish diffuse, KHR_materials_specular 0
  Metal005,         // conductor, GGX alpha 0.05 (roughness 0.224)
  Metal03,          // alpha 0.3 (roughness 0.548)
  Metal1,           // alpha 1
  GlassSmooth,      // transmission 1, ior 1.5, roughness 0: delta reflection and refraction
  GlassRough,       // roughness 0.3 (alpha 0.09), ior 1.5
  GlassAbsorbing,   // rough glass with KHR_materials_volume attenuation (0.9, 0.4, 0.2) / 0.3 m
  GlassSheet,       // an open rough-glass sheet standing in front of a diffuse sphere
  Specular,         // plastic with KHR_materials_specular 0.5 and a coloured specular
  NormalMap,        // plastic whose normal map tilts the shading normal in stripes
  AlphaMask,        // diffuse with an alpha-masked checker of holes
  AlphaBlend,       // diffuse, alpha 0.5 (stochastic transparency)
  EmissiveTexture,  // diffuse with an emissive checker texture (a second, textured light)
  Clearcoat,        // rough red plastic under a glossy KHR_materials_clearcoat
  IridescentGlass,  // rough glass (as GlassRough) under a KHR_materials_iridescence film
  Translucent,      // rough plastic whose diffuse layer transmits 0.6 (KHR_materials_diffuse_transmission)
  Sheen,            // dark red rough plastic under a pale KHR_materials_sheen (roughness 0.25)
  Anisotropic,      // brushed metal: KHR_materials_anisotropy 0.8, rotated 0.5 rad (roughness 0.3)
  DispersiveGlass,  // rough glass (as GlassRough) with KHR_materials_dispersion 2 (Abbe number 10)
};

enum class StageLight {
  AreaDown,     // 0.3 m quad under the ceiling, facing down
  AreaUp,       // 0.12 m panel 10 cm under the ceiling facing up at it, a diffuse shade under it
  AreaSide,     // 0.25 m quad on the left wall, facing +x
  AreaDouble,   // double-sided vertical 0.2 m quad right of the sphere, facing +-x
  Point,        // KHR_lights_punctual point light under the ceiling
  Spot,         // spot light pointing at the sphere, 35 degree cone
  Directional,  // sun from above left (open stage)
  Environment,  // constant background radiance (open stage)
};

std::string stage_material_name(StageMaterial m);
std::string stage_light_name(StageLight l);
bool stage_light_is_delta(StageLight l);  // point, spot, directional

// The scene: stage, object and light, with the camera looking at the object.
Scene stage_scene(StageMaterial material, StageLight light);

// Settings the light needs beyond the scene (the environment's background radiance), for an
// integrator at size x size pixels and spp samples.
RenderSettings stage_settings(StageLight light, const std::string& integrator, uint64_t spp,
                              uint32_t size);

// Pixel regions of a size x size render, from the camera ray through each pixel's centre:
// 0 the object (the sphere or the sheet), 1 the floor within 0.45 m of the object's foot
// (its shadow and caustic), 2 the rest.
enum StageRegion : uint8_t { REGION_OBJECT = 0, REGION_NEAR = 1, REGION_REST = 2, REGION_COUNT = 3 };
std::vector<uint8_t> stage_regions(StageMaterial material, uint32_t size);
const char* stage_region_name(int region);

}  // namespace clpt::test
