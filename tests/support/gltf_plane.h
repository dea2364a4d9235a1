// A glTF file of one tilted square and one material, written for tests that check a
// material extension end to end (file -> loader -> material -> BSDF -> integrator): under a
// constant environment each pixel of a camera on the z axis sees only the environment
// reflected by the plane, L times the BSDF's response at that pixel's view direction.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt::test {

// A 6 m square through the origin tilted 55 degrees about x (its normal, towards a camera at
// (0, 0, z > 0), is tilted_plane_normal()), double-sided, with `material` as its only
// material; `extensions` go to extensionsUsed. Written as <tmp>/clpt-<tag>-<pid>/plane.gltf
// (+ plane.bin); the caller removes the folder.
std::filesystem::path write_tilted_plane(const std::string& tag, const nlohmann::json& material,
                                         const std::vector<std::string>& extensions);
glm::dvec3 tilted_plane_normal();

// The scene of a file write_tilted_plane wrote, its folder removed.
Scene load_tilted_plane(const std::filesystem::path& file);

// The plane seen by a camera on the z axis, 2 m away, with vertical field of view yfov
// (add_camera_on_z), size x size pixels, spp samples of pt seeded with `seed`, under a constant
// sky of radiance 1.
FilmResult render_plane_under_sky(Scene scene, float yfov, uint32_t size, uint32_t spp, uint32_t seed = 0);

}  // namespace clpt::test
