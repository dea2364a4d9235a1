// Procedural triangle meshes for tests: closed spheres and random triangle soups.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace clpt::test {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;  // counter-clockwise seen from outside for the spheres

  size_t triangle_count() const { return triangles.size(); }
  void append(const Mesh& other);  // adds other's triangles, re-indexed
};

// A closed UV sphere: `rings` >= 2 latitude bands, `segments` >= 3 longitude slices, single
// pole vertices (triangle fans there), every edge shared by exactly two triangles.
// 2 * segments * (rings - 1) triangles.
Mesh uv_sphere(glm::vec3 center, float radius, int segments, int rings);

// A closed icosphere: the icosahedron with each face split into 4^subdivisions triangles,
// vertices projected onto the sphere and shared between faces. 20 * 4^subdivisions triangles.
Mesh icosphere(glm::vec3 center, float radius, int subdivisions);

// A closed axis-aligned cube [center - half, center + half] whose faces are grids of
// n x n quads, each split along a diagonal; outward winding. Vertices on the cube's edges
// are repeated per face with identical coordinates. With a power-of-two half size and n,
// grid lines, diagonals and vertices sit at exactly representable coordinates, so
// axis-aligned rays can pass exactly through edges and vertices. 12 * n * n triangles.
Mesh grid_cube(glm::vec3 center, float half, int n);

// n independent triangles with corners uniform in a cube of side `size` around a centre that
// is uniform in [lo, hi]. Deterministic for a seed; triangles may intersect each other.
Mesh random_soup(size_t n, uint32_t seed, glm::vec3 lo, glm::vec3 hi, float size);

// `count` copies of `base`, each scaled by a factor in [min_scale, max_scale] and moved to a
// random point of [lo, hi]: a large scene of small closed objects (e.g. 1M triangles).
Mesh instanced_soup(const Mesh& base, size_t count, uint32_t seed, glm::vec3 lo, glm::vec3 hi,
                    float min_scale, float max_scale);

}  // namespace clpt::test
