// Scenes built in code for tests, with known answers.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "scene/scene.h"
#include "support/mesh.h"

namespace clpt::test {

// Adds a mesh to a scene with one material; normals left zero (flat shading).
void add_mesh(Scene& scene, const Mesh& mesh, const Material& material);

// Adds a square perspective camera at (0, 0, z) looking down -z, with vertical field of view
// yfov (radians).
void add_camera_on_z(Scene& scene, float z, float yfov);

// The furnace: an inner sphere of radius 1 inside a closed sphere of radius 5, both diffuse
// with albedo rho and emitting radiance Le, with a camera inside looking at the inner sphere.
// Every camera ray then sees L = Le (1 - rho^(D+1)) / (1 - rho) at max depth D.
Scene furnace_scene(float rho, float Le);
double furnace_radiance(double rho, double Le, unsigned max_depth);

// One furnace test case of the integrators' SphereFurnace suites: albedo and max depth.
struct FurnaceCase {
  float rho;
  uint32_t max_depth;
};
void PrintTo(const FurnaceCase& c, std::ostream* os);  // gtest's description of a case
std::string furnace_case_name(const FurnaceCase& c);   // e.g. "rho80_depth8"

// The unit direction, in camera space (looking down -z), of the ray through the centre of
// pixel (x, y) of a square size x size pinhole film with vertical field of view yfov: the
// ray the kernels' camera_ray gives for film offset (0.5, 0.5).
glm::vec3 pixel_centre_direction(uint32_t x, uint32_t y, uint32_t size, float yfov);

// Distance along the unit-direction ray (o, d) to where it enters the sphere, or -1 when it
// misses it or starts inside.
float ray_sphere(glm::vec3 o, glm::vec3 d, glm::vec3 c, float r);

// A clear dielectric: white, metallic 0, transmission 1, the given GGX roughness (0: delta)
// and index of refraction, default specular.
Material glass_material(float roughness, float ior = 1.5f);

// The project's Cornell box (scenes/cornell_box.gltf).
Scene cornell_box();

// The Cornell box with a glossy metal tall block (GGX alpha 0.09, roughness 0.3) and a smooth
// glass short block (transmission 1, IOR 1.5): caustics on the floor, the light seen through
// and in delta surfaces.
Scene cornell_box_glossy_glass();

// The Cornell box, open towards the camera, with every light type besides its ceiling light:
// a directional light shining in through the open side, a point and a spot light inside (a
// constant background is the render settings' business).
Scene cornell_box_all_lights();

}  // namespace clpt::test
