// The host half of the lights (light_table.cpp): the environment, and the table of lights
// each weighted by its luminous power, with the alias table the kernels select them by.
// Parts of flatten_scene (render/scene_buffers.h), which calls build_environment and
// build_lights; the tests call them on their own.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/image.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "shared/scene_types.h"

namespace clpt {

struct FlatScene;  // render/scene_buffers.h

// What lights the scene from outside: an equirectangular map or a constant background
// (kernels/light/environment.cl has the mapping). Neither: no environment light.
struct Environment {
  Image map;                   // linear RGB; empty: the constant background
  glm::vec3 background{0.0f};  // radiance of rays that escape when there is no map
  float scale = 1.0f;          // multiplies the map
  float rotation = 0.0f;       // radians about +y
};

// Reads an equirectangular .hdr/.exr (or PNG/JPEG: io/image_io.h) for --env. Negative and
// non-finite texels are set to 0 with a warning. The file's header is checked against
// `limits` before any pixel is read. Throws Error(BadInput) naming the file.
Environment load_environment(const std::string& file, float scale, float rotation_degrees,
                             const ImageLimits& limits = {});

// The environment's texels (RGB, .w = density in (u, v)), its sampling distribution
// (marginal and conditional CDFs of luminance x sin(theta)) and SceneInfo's env fields.
// Sets flat.env_integral; the light itself is added by build_lights.
void build_environment(const Environment& env, FlatScene& flat);

// Integral over cos(theta) in [-1, 1] of the glTF spot falloff (kernels/light/punctual.cl):
// the spot's radiant power is 2 pi x this x its intensity.
double spot_falloff_integral(double cos_outer, double cos_inner);

// Packs selection weights into the lights' alias table (Vose's method) and pdf_select, so the
// kernel picks light i with probability weight[i] / sum in O(1).
void build_alias_table(const std::vector<double>& weight, std::vector<dev::Light>& lights);

// The lights of a scene, each weighted by its luminous power (docs/concepts/lights.md):
// emissive triangles luminance(Le) x area x pi x sides; point lights 4 pi luminance(I); spot
// lights 2 pi luminance(I) x spot_falloff_integral; directional lights pi r^2 luminance(E) and
// the environment pi r^2 x env_integral, r the scene's bounding radius (the power crossing
// the scene's bounding sphere). Needs flat.triangles, flat.info's bounds and build_environment.
void build_lights(const Scene& scene, FlatScene& flat);

}  // namespace clpt
