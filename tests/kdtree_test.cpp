// The photon kd-tree (host/photon/kdtree.*): k-nearest-neighbour and radius queries against
// brute force over degenerate and ordinary point sets, and the tree's structure (heap
// layout, split planes, axis of largest extent).
#include "photon/kdtree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/point_sets.h"
#include "util/error.h"

namespace clpt::kdtree_test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const size_t kSizes[] = {0, 1, 2, 7, 1000, 100000};
const size_t kKs[] = {1, 5, 50, 500};
constexpr size_t kMaxK = 500;

// ---------------------------------------------------------------------------------------
// Point sets

struct PointSet {
  std::string name;
  std::vector<glm::vec3> points;
};

using Generator = std::function<std::vector<glm::vec3>(size_t n, std::mt19937& rng)>;

struct Distribution {
  const char* name;
  Generator make;
};

std::vector<glm::vec3> lattice12(size_t n, std::mt19937& rng) { return test::lattice(n, rng, 12); }

const Distribution kDistributions[] = {
    {"uniform", test::uniform_cube},     {"blobs", test::blobs},  {"plane", test::plane},
    {"duplicates", test::duplicates},    {"lattice", lattice12},  {"identical", test::identical},
};

// Radii: 0 (coincident photons only), small (a few photons in the dense parts), large (a
// good part of the cloud) and infinite. Each query adds a fifth: the distance to its 50th
// nearest photon, which puts a photon on (or within rounding of) the sphere.
std::vector<float> radii(const std::vector<glm::vec3>& points) {
  const test::PointBox b = test::bounds(points);
  float diagonal = glm::length(b.hi - b.lo);
  if (!(diagonal > 0.0f)) diagonal = 1.0f;
  return {0.0f, 0.02f * diagonal, 0.4f * diagonal, kInf};
}

size_t query_count(size_t n) { return n >= 100000 ? 100 : 300; }

std::string describe(const char* dist, size_t n, const glm::vec3& q, size_t k, float r) {
  std::ostringstream s;
  s << dist << " n=" << n << " query (" << q.x << ", " << q.y << ", " << q.z << ")";
  if (k) s << " k=" << k;
  s << " radius=" << r;
  return s.str();
}

// ---------------------------------------------------------------------------------------
// Brute force

struct Candidate {
  float distance2;
  uint32_t index;
  bool operator<(const Candidate& o) const {
    return distance2 < o.distance2 || (distance2 == o.distance2 && index < o.index);
  }
};

// Checks one kNN answer against the sorted prefix of the brute-force order (the kMaxK
// nearest, ascending). Returns an empty string when it is right.
std::string check_knn(const std::vector<KdNeighbor>& got, size_t returned,
                      const std::vector<Candidate>& nearest, const std::vector<glm::vec3>& points,
                      const glm::vec3& q, size_t k, float r, std::vector<uint32_t>& stamp,
                      uint32_t& stamp_id) {
  const float r2 = r * r;
  size_t expected = 0;
  while (expected < nearest.size() && expected < k && nearest[expected].distance2 <= r2) ++expected;
  std::ostringstream s;
  if (returned != got.size()) s << "returned " << returned << " but out has " << got.size();
  else if (got.size() != expected) s << got.size() << " neighbours, brute force " << expected;
  if (!s.str().empty()) return s.str();
  ++stamp_id;
  for (size_t j = 0; j < got.size(); ++j) {
    const KdNeighbor& e = got[j];
    // Same distances position by position: sorted, and the same multiset as the brute force
    // (so ties at the k-th distance may be any of the tied photons).
    if (!test::neighbour_ok(s, points, q, j, e.distance2, e.index, nearest[j].distance2,
                            "brute force"))
      return s.str();
    if (stamp[e.index] == stamp_id) {
      s << "photon " << e.index << " returned twice";
      return s.str();
    }
    stamp[e.index] = stamp_id;
  }
  return {};
}

// ---------------------------------------------------------------------------------------
// Tests

TEST(KdTree, KnnEqualsBruteForce) {
  std::mt19937 rng(7);
  int failures = 0;
  size_t checked = 0;
  std::vector<KdNeighbor> got;
  std::vector<Candidate> all;
  for (const Distribution& dist : kDistributions) {
    for (size_t n : kSizes) {
      const std::vector<glm::vec3> points = dist.make(n, rng);
      const KdTree tree = build_kdtree(points);
      ASSERT_EQ(tree.size(), n);
      const std::vector<float> rs = radii(points);
      std::vector<uint32_t> stamp(n, 0);
      uint32_t stamp_id = 0;
      for (const glm::vec3& q : test::query_points(points, query_count(n), rng)) {
        all.resize(n);
        for (uint32_t i = 0; i < n; ++i) all[i] = {test::distance2(q, points[i]), i};
        const size_t prefix = std::min(n, kMaxK);
        std::partial_sort(all.begin(), all.begin() + prefix, all.end());
        all.resize(prefix);
        std::vector<float> rq = rs;
        if (n > 0) rq.push_back(std::sqrt(all[std::min<size_t>(n, 50) - 1].distance2));
        for (size_t k : kKs) {
          for (float r : rq) {
            const size_t returned = tree.knn(q, k, r, got);
            const std::string error = check_knn(got, returned, all, points, q, k, r, stamp, stamp_id);
            ++checked;
            if (!error.empty() && ++failures <= 5)
              ADD_FAILURE() << describe(dist.name, n, q, k, r) << ": " << error;
          }
        }
        // k = 0 and a negative radius ask for nothing.
        EXPECT_EQ(tree.knn(q, 0, kInf, got), 0u);
        EXPECT_TRUE(got.empty());
        EXPECT_EQ(tree.knn(q, 5, -1.0f, got), 0u);
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checked << " kNN queries";
  std::cout << "[ figures  ] " << checked << " kNN queries checked, " << failures << " wrong\n";
}

TEST(KdTree, RadiusEqualsBruteForce) {
  std::mt19937 rng(11);
  int failures = 0;
  size_t checked = 0, found = 0;
  std::vector<KdNeighbor> got;
  for (const Distribution& dist : kDistributions) {
    for (size_t n : kSizes) {
      const std::vector<glm::vec3> points = dist.make(n, rng);
      const KdTree tree = build_kdtree(points);
      ASSERT_EQ(tree.size(), n);
      const std::vector<float> rs = radii(points);
      std::vector<uint32_t> seen(n, 0);
      std::vector<float> d2(n);
      uint32_t id = 0;
      const std::vector<glm::vec3> qs = test::query_points(points, query_count(n), rng);
      for (size_t qi = 0; qi < qs.size(); ++qi) {
        const glm::vec3& q = qs[qi];
        for (uint32_t i = 0; i < n; ++i) d2[i] = test::distance2(q, points[i]);
        std::vector<float> rq = rs;
        if (n > 0) {
          std::vector<float> sorted = d2;
          const size_t rank = std::min<size_t>(n, 50) - 1;
          std::nth_element(sorted.begin(), sorted.begin() + rank, sorted.end());
          rq.push_back(std::sqrt(sorted[rank]));
        }
        for (size_t ri = 0; ri < rq.size(); ++ri) {
          const float r = rq[ri];
          // The large and infinite radii return most of the cloud: at 100 000 photons, 20
          // queries (5 of each kind) are enough for them.
          if (n >= 100000 && qi >= 20 && (ri == 2 || ri == 3)) continue;
          ++id;
          const float r2 = r * r;
          size_t expected = 0;
          for (uint32_t i = 0; i < n; ++i) expected += d2[i] <= r2;
          const size_t returned = tree.within(q, r, got);
          // Right count, and every one returned inside the radius, once, with its distance.
          std::ostringstream s;
          if (returned != got.size()) s << "returned " << returned << " but out has " << got.size();
          else if (got.size() != expected) s << got.size() << " photons, brute force " << expected;
          for (size_t j = 0; j < got.size() && s.str().empty(); ++j) {
            const KdNeighbor& e = got[j];
            if (e.index >= n) s << "index " << e.index << " of " << n;
            else if (!(d2[e.index] <= r2)) s << "photon " << e.index << " is outside the radius";
            else if (seen[e.index] == id) s << "photon " << e.index << " returned twice";
            else if (d2[e.index] != e.distance2)
              s << "photon " << e.index << " reports distance2 " << e.distance2 << ", true " << d2[e.index];
            else seen[e.index] = id;
          }
          ++checked;
          found += got.size();
          if (!s.str().empty() && ++failures <= 5)
            ADD_FAILURE() << describe(dist.name, n, q, 0, r) << ": " << s.str();
        }
        EXPECT_EQ(tree.within(q, -1.0f, got), 0u);
        EXPECT_EQ(tree.within(q, std::nanf(""), got), 0u);
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checked << " radius queries";
  std::cout << "[ figures  ] " << checked << " radius queries checked (" << found
            << " photons found), " << failures << " wrong\n";
}

// Structure: n nodes holding each input photon once with its exact position; the heap is
// complete by construction of the implicit layout (slots 0..n-1, children 2i+1 and 2i+2), so
// what can go wrong is a slot left unfilled or filled twice (the permutation check), a wrong
// leaf mark, a photon on the wrong side of an ancestor's split plane, or a split axis that is
// not the subtree's axis of largest extent. Returns the number of violations.
size_t check_structure(const KdTree& tree, const std::vector<glm::vec3>& points, const std::string& what) {
  const size_t n = points.size();
  size_t bad = 0;
  auto fail = [&](const std::string& msg) {
    if (++bad <= 5) ADD_FAILURE() << what << ": " << msg;
  };
  if (tree.size() != n) {
    fail("node count " + std::to_string(tree.size()) + ", photons " + std::to_string(n));
    return bad;
  }
  int expected_height = 0;
  while (expected_height < 40 && (size_t{1} << expected_height) <= n) ++expected_height;  // floor(log2 n) + 1
  if (tree.height() != expected_height)
    fail("height " + std::to_string(tree.height()) + ", expected " + std::to_string(expected_height));
  if (expected_height - 1 > kKdMaxStack) fail("deeper than the query stack");

  std::vector<char> used(n, 0);
  const std::vector<KdNode>& nodes = tree.nodes;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t index = kd_photon_index(nodes[i]);
    const uint32_t axis = kd_split_axis(nodes[i]);
    if (index >= n || used[index]) {
      fail("slot " + std::to_string(i) + " holds photon " + std::to_string(index) + " (out of range or repeated)");
      continue;
    }
    used[index] = 1;
    const glm::vec3& p = points[index];
    if (nodes[i].pos[0] != p.x || nodes[i].pos[1] != p.y || nodes[i].pos[2] != p.z)
      fail("slot " + std::to_string(i) + " has another position than photon " + std::to_string(index));
    const bool leaf = 2 * i + 1 >= n;
    if (leaf != (axis == kKdLeafAxis))
      fail("slot " + std::to_string(i) + (leaf ? " is a leaf but has axis " : " is interior but has axis ") +
           std::to_string(axis));
  }
  if (bad) return bad;

  // Split planes: every node against each of its ancestors.
  for (size_t j = 1; j < n; ++j) {
    for (size_t c = j; c > 0;) {
      const size_t a = (c - 1) / 2;
      const uint32_t axis = kd_split_axis(nodes[a]);
      const float v = nodes[j].pos[axis], split = nodes[a].pos[axis];
      const bool left = c == 2 * a + 1;
      if (left ? v > split : v < split)
        fail("slot " + std::to_string(j) + " lies on the wrong side of slot " + std::to_string(a) + "'s plane");
      c = a;
    }
  }
  // Axis of largest extent of each subtree's photons (subtree boxes bottom-up).
  std::vector<test::PointBox> box(n);
  for (size_t i = n; i-- > 0;) {
    const glm::vec3 p(nodes[i].pos[0], nodes[i].pos[1], nodes[i].pos[2]);
    box[i] = {p, p};
    for (size_t c : {2 * i + 1, 2 * i + 2}) {
      if (c < n) {
        box[i].lo = glm::min(box[i].lo, box[c].lo);
        box[i].hi = glm::max(box[i].hi, box[c].hi);
      }
    }
    const uint32_t axis = kd_split_axis(nodes[i]);
    if (axis == kKdLeafAxis) continue;
    const glm::vec3 extent = box[i].hi - box[i].lo;
    if (extent[axis] < std::max({extent.x, extent.y, extent.z}))
      fail("slot " + std::to_string(i) + " splits on axis " + std::to_string(axis) +
           ", not its subtree's longest");
  }
  return bad;
}

TEST(KdTree, IsBalanced) {
  std::mt19937 rng(3);
  // Every size up to 70 (every shape of the last level), then the sizes of the other tests.
  for (size_t n = 0; n <= 70; ++n) {
    const auto points = test::uniform_cube(n, rng);
    EXPECT_EQ(check_structure(build_kdtree(points), points, "uniform n=" + std::to_string(n)), 0u);
  }
  for (const Distribution& dist : kDistributions) {
    for (size_t n : kSizes) {
      const auto points = dist.make(n, rng);
      EXPECT_EQ(check_structure(build_kdtree(points), points,
                                std::string(dist.name) + " n=" + std::to_string(n)), 0u);
    }
  }
  EXPECT_EQ(build_kdtree({}).height(), 0);
  EXPECT_THROW(build_kdtree({glm::vec3(0.0f), glm::vec3(std::nanf(""), 0.0f, 0.0f)}), Error);
  EXPECT_THROW(build_kdtree({glm::vec3(kInf, 0.0f, 0.0f)}), Error);

  // A million photons: structure, a few queries against brute force, and the figures.
  const size_t n = 1000000;
  const auto points = test::uniform_cube(n, rng);
  const auto t0 = std::chrono::steady_clock::now();
  const KdTree tree = build_kdtree(points);
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_EQ(check_structure(tree, points, "uniform n=1000000"), 0u);

  const std::vector<glm::vec3> qs = test::query_points(points, 4000, rng);
  std::vector<KdNeighbor> got;
  size_t total = 0;
  double seconds[4] = {0, 0, 0, 0};  // by query kind: on, near, in the box, outside
  for (int kind = 0; kind < 4; ++kind) {
    const auto t2 = std::chrono::steady_clock::now();
    for (size_t i = kind; i < qs.size(); i += 4) total += tree.knn(qs[i], 50, kInf, got);
    seconds[kind] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t2).count();
  }
  EXPECT_EQ(total, 50 * qs.size());

  std::vector<Candidate> all(n);
  std::vector<uint32_t> stamp(n, 0);
  uint32_t stamp_id = 0;
  for (size_t i = 0; i < 8; ++i) {
    const glm::vec3& q = qs[i];
    all.resize(n);
    for (uint32_t j = 0; j < n; ++j) all[j] = {test::distance2(q, points[j]), j};
    std::partial_sort(all.begin(), all.begin() + 50, all.end());
    all.resize(50);
    tree.knn(q, 50, kInf, got);
    EXPECT_EQ(check_knn(got, got.size(), all, points, q, 50, kInf, stamp, stamp_id), "")
        << describe("uniform", n, q, 50, kInf);
  }

  const double per_kind = static_cast<double>(qs.size() / 4);
  char line[400];
  std::snprintf(line, sizeof line,
                "[ figures  ] kd-tree of 1,000,000 uniform photons: build %.0f ms (%u threads); "
                "k = 50, unbounded radius, mean over %zu queries each: %.1f us at a photon, "
                "%.1f us near one, %.1f us anywhere in the box, %.1f us outside it\n",
                std::chrono::duration<double, std::milli>(t1 - t0).count(),
                std::max(1u, std::thread::hardware_concurrency()), qs.size() / 4,
                1e6 * seconds[0] / per_kind, 1e6 * seconds[1] / per_kind,
                1e6 * seconds[2] / per_kind, 1e6 * seconds[3] / per_kind);
  std::cout << line;
}

}  // namespace
}  // namespace clpt::kdtree_test
