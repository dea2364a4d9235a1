// Per-vertex tangents for normal mapping when a glTF primitive has no TANGENT attribute.
//
// Not MikkTSpace (it is not packaged in Debian 12): per-triangle tangents from the UV
// derivatives (Lengyel 2001), summed per vertex, made orthogonal to the vertex normal by
// Gram-Schmidt. It agrees with MikkTSpace on smooth, well-parametrised meshes; along UV seams
// and on degenerate UV triangles the two differ.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace clpt {

// Tangents in the space of `positions`: xyz unit along increasing u, w = +-1 so that
// w * cross(normal, tangent) points along decreasing v (glTF: image row 0 is v = 0, and the
// normal map's +Y is up in the image). `normals` may be empty (face normals are then used).
// A vertex whose triangles all have degenerate UVs gets a zero tangent (no normal mapping).
std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& normals,
                                         const std::vector<glm::vec2>& uvs,
                                         const std::vector<glm::uvec3>& triangles);

}  // namespace clpt
