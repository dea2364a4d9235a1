#include "support/mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

namespace clpt::test {

void Mesh::append(const Mesh& other) {
  const auto base = static_cast<uint32_t>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const glm::uvec3& t : other.triangles) triangles.push_back(t + glm::uvec3(base));
}

Mesh uv_sphere(glm::vec3 center, float radius, int segments, int rings) {
  segments = std::max(segments, 3);
  rings = std::max(rings, 2);
  const double pi = 3.14159265358979323846;
  Mesh m;
  m.positions.push_back(center + glm::vec3(0.0f, radius, 0.0f));  // north pole, index 0
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * pi * s / segments;
      const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi));
      m.positions.push_back(center + glm::vec3(d * double(radius)));
    }
  }
  const auto south = static_cast<uint32_t>(m.positions.size());
  m.positions.push_back(center - glm::vec3(0.0f, radius, 0.0f));

  auto ring_vertex = [&](int r, int s) {  // r in [1, rings - 1]
    return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments));
  };
  // phi grows counter-clockwise seen from +Y, so (pole, s, s + 1) faces outwards.
  for (int s = 0; s < segments; ++s) m.triangles.emplace_back(0, ring_vertex(1, s), ring_vertex(1, s + 1));
  for (int r = 1; r < rings - 1; ++r) {
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
      const uint32_t c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
      m.triangles.emplace_back(a, c, d);
      m.triangles.emplace_back(a, d, b);
    }
  }
  for (int s = 0; s < segments; ++s)
    m.triangles.emplace_back(south, ring_vertex(rings - 1, s + 1), ring_vertex(rings - 1, s));
  return m;
}

Mesh icosphere(glm::vec3 center, float radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> dirs = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                  {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                  {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& d : dirs) d = glm::normalize(d);
  std::vector<glm::uvec3> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
      const auto index = static_cast<uint32_t>(dirs.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<glm::uvec3> next;
    next.reserve(faces.size() * 4);
    for (const glm::uvec3& f : faces) {
      const uint32_t ab = midpoint(f.x, f.y), bc = midpoint(f.y, f.z), ca = midpoint(f.z, f.x);
      next.emplace_back(f.x, ab, ca);
      next.emplace_back(f.y, bc, ab);
      next.emplace_back(f.z, ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    faces = std::move(next);
  }
  Mesh m;
  m.positions.reserve(dirs.size());
  for (const auto& d : dirs) m.positions.push_back(center + glm::vec3(d * double(radius)));
  m.triangles = std::move(faces);
  return m;
}

Mesh grid_cube(glm::vec3 center, float half, int n) {
  n = std::max(n, 1);
  Mesh m;
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;  // e_b x e_c = e_axis
    for (int side = -1; side <= 1; side += 2) {
      const auto first = static_cast<uint32_t>(m.positions.size());
      for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
          glm::vec3 p = center;
          p[axis] += float(side) * half;
          p[b] += half * (2.0f * float(i) / float(n) - 1.0f);
          p[c] += half * (2.0f * float(j) / float(n) - 1.0f);
          m.positions.push_back(p);
        }
      }
      auto at = [&](int i, int j) { return first + static_cast<uint32_t>(j * (n + 1) + i); };
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const uint32_t p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          if (side > 0) {
            m.triangles.emplace_back(p00, p10, p11);
            m.triangles.emplace_back(p00, p11, p01);
          } else {
            m.triangles.emplace_back(p00, p11, p10);
            m.triangles.emplace_back(p00, p01, p11);
          }
        }
      }
    }
  }
  return m;
}

Mesh random_soup(size_t n, uint32_t seed, glm::vec3 lo, glm::vec3 hi, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  auto in_box = [&](glm::vec3 a, glm::vec3 b) {
    return a + (b - a) * glm::vec3(u01(rng), u01(rng), u01(rng));
  };
  Mesh m;
  m.positions.reserve(3 * n);
  m.triangles.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 c = in_box(lo, hi);
    const auto base = static_cast<uint32_t>(m.positions.size());
    for (int k = 0; k < 3; ++k) m.positions.push_back(c + in_box(glm::vec3(-0.5f * size), glm::vec3(0.5f * size)));
    m.triangles.emplace_back(base, base + 1, base + 2);
  }
  return m;
}

Mesh instanced_soup(const Mesh& base, size_t count, uint32_t seed, glm::vec3 lo, glm::vec3 hi,
                    float min_scale, float max_scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  Mesh m;
  m.positions.reserve(base.positions.size() * count);
  m.triangles.reserve(base.triangles.size() * count);
  for (size_t i = 0; i < count; ++i) {
    const glm::vec3 offset = lo + (hi - lo) * glm::vec3(u01(rng), u01(rng), u01(rng));
    const float scale = min_scale + (max_scale - min_scale) * u01(rng);
    const auto first = static_cast<uint32_t>(m.positions.size());
    for (const glm::vec3& p : base.positions) m.positions.push_back(offset + scale * p);
    for (const glm::uvec3& t : base.triangles) m.triangles.push_back(t + glm::uvec3(first));
  }
  return m;
}

}  // namespace clpt::test
