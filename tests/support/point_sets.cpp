#include "support/point_sets.h"

#include <cmath>

namespace clpt::test {

float distance2(const glm::vec3& a, const glm::vec3& b) {
  const float dx = a.x - b.x;
  const float dy = a.y - b.y;
  const float dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

std::vector<glm::vec3> uniform_cube(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> p(n);
  for (auto& x : p) x = {u(rng), u(rng), u(rng)};
  return p;
}

std::vector<glm::vec3> blobs(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  glm::vec3 centre[8];
  float sigma[8];
  for (int b = 0; b < 8; ++b) {
    centre[b] = {u(rng), u(rng), u(rng)};
    sigma[b] = 0.002f * std::pow(3.0f, static_cast<float>(b));  // 0.002 .. 4.4
  }
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<glm::vec3> p(n);
  for (auto& x : p) {
    const int b = static_cast<int>(rng() % 8);
    x = centre[b] + sigma[b] * glm::vec3(g(rng), g(rng), g(rng));
  }
  return p;
}

std::vector<glm::vec3> plane(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> p(n);
  for (auto& x : p) x = {u(rng), 0.25f, u(rng)};
  return p;
}

std::vector<glm::vec3> duplicates(size_t n, std::mt19937& rng) {
  const std::vector<glm::vec3> pool = uniform_cube(n / 50 + 1, rng);
  std::vector<glm::vec3> p(n);
  for (auto& x : p) x = pool[rng() % pool.size()];
  return p;
}

std::vector<glm::vec3> lattice(size_t n, std::mt19937& rng, unsigned cells) {
  std::vector<glm::vec3> p(n);
  for (auto& x : p)
    x = 0.25f * glm::vec3(static_cast<float>(rng() % cells), static_cast<float>(rng() % cells),
                          static_cast<float>(rng() % cells));
  return p;
}

std::vector<glm::vec3> identical(size_t n, std::mt19937&) {
  return std::vector<glm::vec3>(n, glm::vec3(0.3f, -0.7f, 2.0f));
}

PointBox bounds(const std::vector<glm::vec3>& points) {
  PointBox b;
  for (const auto& p : points) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  if (points.empty()) b = {glm::vec3(-1.0f), glm::vec3(1.0f)};
  return b;
}

std::vector<glm::vec3> query_points(const std::vector<glm::vec3>& points, size_t count,
                                    std::mt19937& rng) {
  const PointBox b = bounds(points);
  const glm::vec3 size = glm::max(b.hi - b.lo, glm::vec3(1e-3f));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<glm::vec3> q(count);
  for (size_t i = 0; i < count; ++i) {
    const int kind = static_cast<int>(i % 4);
    if (kind < 2 && !points.empty()) {
      q[i] = points[rng() % points.size()];
      if (kind == 1) q[i] += 0.01f * size * glm::vec3(g(rng), g(rng), g(rng));
    } else if (kind == 2) {
      q[i] = b.lo + size * glm::vec3(u(rng), u(rng), u(rng));
    } else {
      glm::vec3 t;
      do t = glm::vec3(u(rng), u(rng), u(rng)) * 7.0f - 3.0f;  // [-3, 4] box units
      while (t.x >= 0 && t.x <= 1 && t.y >= 0 && t.y <= 1 && t.z >= 0 && t.z <= 1);
      q[i] = b.lo + size * t;
    }
  }
  return q;
}

bool neighbour_ok(std::ostream& out, const std::vector<glm::vec3>& points, const glm::vec3& q,
                  size_t j, float d2, uint32_t index, float expected_d2, const char* source) {
  if (d2 != expected_d2)
    out << "neighbour " << j << " at distance2 " << d2 << ", " << source << " " << expected_d2;
  else if (index >= points.size())
    out << "neighbour " << j << " has index " << index << " of " << points.size();
  else if (distance2(q, points[index]) != d2)
    out << "neighbour " << j << " (photon " << index << ") reports distance2 " << d2 << ", true "
        << distance2(q, points[index]);
  else
    return true;
  return false;
}

}  // namespace clpt::test
