// Point sets for the photon kd-tree and photon map tests (kdtree_test.cpp,
// photon_map_test.cpp): ordinary and degenerate clouds, and query points on, near, among
// and outside them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <ostream>
#include <random>
#include <vector>

#include <glm/glm.hpp>

namespace clpt::test {

// The kd-tree's distance, as the tree and the kernels compute it (same order, no fused
// multiply-add): distances compare exactly, so ties are ties on every side.
float distance2(const glm::vec3& a, const glm::vec3& b);

std::vector<glm::vec3> uniform_cube(size_t n, std::mt19937& rng);  // in [-1, 1]^3
// Eight Gaussian blobs of widths 0.002 to 4.4.
std::vector<glm::vec3> blobs(size_t n, std::mt19937& rng);
// On the plane y = 0.25: one axis has no extent at all.
std::vector<glm::vec3> plane(size_t n, std::mt19937& rng);
// Drawn from n / 50 + 1 distinct points: about 50 copies of each.
std::vector<glm::vec3> duplicates(size_t n, std::mt19937& rng);
// Points of a lattice of `cells`^3 points with spacing 0.25 (exact in float): many equal
// coordinates and, from lattice query points, many equal distances.
std::vector<glm::vec3> lattice(size_t n, std::mt19937& rng, unsigned cells);
// n copies of one point.
std::vector<glm::vec3> identical(size_t n, std::mt19937& rng);

struct PointBox {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
};
// The bounding box of the points; [-1, 1]^3 when there are none.
PointBox bounds(const std::vector<glm::vec3>& points);

// Query points: a quarter exactly on the points, a quarter near them, a quarter anywhere in
// their bounding box, a quarter outside it (up to 3 box sizes away).
std::vector<glm::vec3> query_points(const std::vector<glm::vec3>& points, size_t count,
                                    std::mt19937& rng);

// Checks neighbour j (squared distance d2, photon `index`) of a kNN answer for query q against
// the squared distance expected at position j (`source` says whose: "brute force", "host"):
// the distances must be equal, the index must name a point, and d2 must be that point's true
// distance. Writes what is wrong to `out` and returns false, or returns true. Repeated
// photons are the caller's to find.
bool neighbour_ok(std::ostream& out, const std::vector<glm::vec3>& points, const glm::vec3& q,
                  size_t j, float d2, uint32_t index, float expected_d2, const char* source);

}  // namespace clpt::test
