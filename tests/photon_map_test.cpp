// Photon maps on the PoCL device, against the host:
//   PhotonKnn.DeviceEqualsHost       kd_knn (kernels/spatial/kdtree.cl) against KdTree::knn
//                                    (host/photon/kdtree.cpp) on the same trees: uniform,
//                                    clustered, planar, duplicated, coincident and lattice
//                                    points, 0, 1, 7 and 50 000 of them; queries on, near,
//                                    among and far outside the photons; k = 1, 8, 50 and
//                                    PM_KNN_MAX; radius 0, small, through a photon, infinite.
//                                    Same count, the same distances (exactly: the same float
//                                    arithmetic), the same photons but for ties at the k-th
//                                    distance, and the device's heap a max-heap;
//   PhotonGrid.GatherEqualsBruteForce  the SPPM hash grid (kernels/spatial/hash_grid.cl): every
//                                    photon in exactly one bucket list, and a gather walking
//                                    the grid as sppm_gather does finds each photon within r
//                                    (r up to the cell side) exactly once, with buckets that
//                                    collide (255 of them) and a normal table, for photons
//                                    clustered, at negative coordinates, far away and exactly
//                                    on cell boundaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "photon/kdtree.h"
#include "shared/photon_types.h"
#include "shared/render_types.h"
#include "support/device.h"
#include "support/point_sets.h"

namespace clpt::photon_map_test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

const cl::Program& photon_map_program() { return test::test_program("kernels/photon_map_test.cl"); }

// ---------------------------------------------------------------------------------------
// PhotonKnn

std::vector<glm::vec3> lattice10(size_t n, std::mt19937& rng) { return test::lattice(n, rng, 10); }

struct PointSetSpec {
  const char* name;
  std::function<std::vector<glm::vec3>(size_t, std::mt19937&)> make;
  size_t n;
  size_t queries;
};

const PointSetSpec kPointSets[] = {
    {"uniform", test::uniform_cube, 3000, 200},     {"clusters", test::blobs, 5000, 200},
    {"plane", test::plane, 3000, 200},              {"duplicates", test::duplicates, 3000, 200},
    {"identical", test::identical, 500, 40},        {"lattice", lattice10, 2000, 200},
    {"empty", test::uniform_cube, 0, 20},           {"one", test::uniform_cube, 1, 20},
    {"seven", test::blobs, 7, 40},                  {"large", test::blobs, 50000, 100},
};
const uint32_t kKs[] = {1, 8, 50, PM_KNN_MAX};

// One query: the point and the radius, the device getting max_r2 = radius^2 as the host
// computes it.
struct KnnQuery {
  glm::vec3 p;
  float radius;
};

// Each query point with radius 0 (coincident photons only), 0.069 (2 % of the diagonal of
// [-1, 1]^3, where most sets lie), the distance to its 20th nearest photon (a photon on the
// sphere, or within rounding of it) and infinity.
std::vector<KnnQuery> knn_queries(const KdTree& tree, const std::vector<glm::vec3>& points,
                                  size_t count, std::mt19937& rng) {
  std::vector<KnnQuery> out;
  std::vector<KdNeighbor> nearest;
  const float small = 0.02f * 2.0f * std::sqrt(3.0f);
  for (const glm::vec3& q : test::query_points(points, count, rng)) {
    out.push_back({q, 0.0f});
    out.push_back({q, small});
    if (tree.knn(q, 20, kInf, nearest) > 0) out.push_back({q, std::sqrt(nearest.back().distance2)});
    out.push_back({q, kInf});
  }
  return out;
}

struct DeviceKnn {
  std::vector<uint32_t> counts;
  std::vector<KdNeighbor> heaps;  // query i's at [i * k, i * k + counts[i])
};

DeviceKnn run_knn(const KdTree& tree, const std::vector<KnnQuery>& queries, uint32_t k) {
  cl::Context& ctx = test::device_context();
  const uint32_t n = static_cast<uint32_t>(tree.size());
  const uint32_t count = static_cast<uint32_t>(queries.size());
  std::vector<glm::vec4> packed(count);
  for (uint32_t i = 0; i < count; ++i)
    packed[i] = glm::vec4(queries[i].p, queries[i].radius * queries[i].radius);
  cl::Buffer nodes = cl::Buffer::from_vector(ctx, tree.nodes);
  cl::Buffer q = cl::Buffer::from_vector(ctx, packed);
  cl::Buffer counts(ctx, count * sizeof(uint32_t), CL_MEM_WRITE_ONLY, nullptr, "counts");
  cl::Buffer heaps(ctx, size_t(count) * k * sizeof(KdNeighbor), CL_MEM_WRITE_ONLY, nullptr, "heaps");
  cl::Kernel kernel(photon_map_program(), "knn_queries");
  kernel.args(0, nodes, n, q, count, k, counts, heaps);
  kernel.launch(ctx, count);
  return {counts.read_vector<uint32_t>(count), heaps.read_vector<KdNeighbor>(size_t(count) * k)};
}

// Compares the device's answer (heap: heap order) with the host's (want: ascending).
// Returns an empty string when they agree.
std::string compare_knn(std::vector<KdNeighbor> heap, const std::vector<KdNeighbor>& want,
                        const std::vector<glm::vec3>& points, const glm::vec3& q) {
  std::ostringstream s;
  s << std::setprecision(9);  // distances that differ in the last bit print differently
  if (heap.size() != want.size()) {
    s << heap.size() << " neighbours, host " << want.size();
    return s.str();
  }
  for (size_t j = 1; j < heap.size(); ++j)
    if (heap[(j - 1) / 2].distance2 < heap[j].distance2) {
      s << "not a max-heap: entry " << j << " is farther than its parent";
      return s.str();
    }
  std::sort(heap.begin(), heap.end(), [](const KdNeighbor& a, const KdNeighbor& b) {
    return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
  });
  for (size_t j = 0; j < heap.size(); ++j) {
    const KdNeighbor& e = heap[j];
    if (!test::neighbour_ok(s, points, q, j, e.distance2, e.index, want[j].distance2, "host"))
      return s.str();
    if (j > 0 && e.index == heap[j - 1].index && e.distance2 == heap[j - 1].distance2) {
      s << "photon " << e.index << " returned twice";
      return s.str();
    }
  }
  // The same photons below the farthest distance; those at it are interchangeable (the
  // distances matched, so both sides hold equally many of them).
  std::vector<uint32_t> got_closer, want_closer;
  const float farthest = want.empty() ? 0.0f : want.back().distance2;
  for (size_t j = 0; j < want.size(); ++j) {
    if (heap[j].distance2 < farthest) got_closer.push_back(heap[j].index);
    if (want[j].distance2 < farthest) want_closer.push_back(want[j].index);
  }
  std::sort(got_closer.begin(), got_closer.end());
  std::sort(want_closer.begin(), want_closer.end());
  if (got_closer != want_closer) s << "different photons nearer than the farthest";
  return s.str();
}

TEST(PhotonKnn, DeviceEqualsHost) {
  std::mt19937 rng(17);
  int failures = 0;
  size_t checked = 0;
  std::vector<KdNeighbor> want;
  for (const PointSetSpec& set : kPointSets) {
    const std::vector<glm::vec3> points = set.make(set.n, rng);
    const KdTree tree = build_kdtree(points);
    const std::vector<KnnQuery> queries = knn_queries(tree, points, set.queries, rng);
    for (uint32_t k : kKs) {
      const DeviceKnn got = run_knn(tree, queries, k);
      for (size_t i = 0; i < queries.size(); ++i) {
        const KnnQuery& q = queries[i];
        tree.knn(q.p, k, q.radius, want);
        const auto first = got.heaps.begin() + std::ptrdiff_t(i * k);
        const std::string error = compare_knn({first, first + std::min(got.counts[i], k)}, want,
                                              points, q.p);
        ++checked;
        if (!error.empty() && ++failures <= 5)
          ADD_FAILURE() << set.name << " n=" << set.n << " query (" << q.p.x << ", " << q.p.y
                        << ", " << q.p.z << ") k=" << k << " radius=" << q.radius << ": " << error
                        << (got.counts[i] > k ? " (count above k)" : "");
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checked << " kNN queries";
}

// ---------------------------------------------------------------------------------------
// PhotonGrid

constexpr float kCell = 0.25f;  // the grids' smallest cell side; a power of two, so the
                                // boundaries k * kCell are exact
constexpr uint32_t kPhotons = 20000;

// 20 000 photons: uniform in [-2, 2]^3 (half at negative coordinates), Gaussian clusters
// (hundreds of photons to a cell), on cell boundaries (one, two or three coordinates
// multiples of kCell, so they sit on faces, edges and corners), coincident pairs, and a few
// far away (cells in the tens of thousands, which hash anywhere).
std::vector<glm::vec3> grid_photons(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<glm::vec3> p;
  p.reserve(kPhotons);
  for (int i = 0; i < 8000; ++i) p.push_back({u(rng), u(rng), u(rng)});
  const glm::vec3 centres[] = {{0.1f, 0.2f, 0.3f}, {-1.0f, -1.0f, -1.0f}, {-0.5f, 1.2f, -1.7f}};
  const float sigmas[] = {0.01f, 0.03f, 0.1f};
  for (int i = 0; i < 6000; ++i)
    p.push_back(centres[i % 3] + sigmas[i % 3] * glm::vec3(g(rng), g(rng), g(rng)));
  for (int i = 0; i < 4000; ++i) {
    glm::vec3 x(u(rng), u(rng), u(rng));
    for (int a = 0; a < 3; ++a)
      if (a <= i % 3 || rng() % 2) x[a] = kCell * std::round(x[a] / kCell);
    p.push_back(x);
  }
  for (int i = 0; i < 1500; ++i) p.push_back(p[rng() % p.size()]);
  std::uniform_real_distribution<float> far(-1e4f, 1e4f);
  while (p.size() < kPhotons) p.push_back({far(rng), far(rng), far(rng)});
  return p;
}

// Gather queries (xyz, w = r): on photons, anywhere in the photons' box, on cell corners
// and on cell faces; r is 0, the cell side, or anywhere between.
std::vector<glm::vec4> gather_queries(const std::vector<glm::vec3>& photons, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-2.2f, 2.2f), unit(0.0f, 1.0f);
  std::vector<glm::vec4> q;
  for (int i = 0; i < 3000; ++i) {
    glm::vec3 x;
    switch (i % 4) {
      case 0: x = photons[rng() % 14000]; break;  // uniform or clustered photons
      case 1: x = {u(rng), u(rng), u(rng)}; break;
      case 2: x = kCell * glm::round(glm::vec3(u(rng), u(rng), u(rng)) / kCell); break;
      default: x = {kCell * std::round(u(rng) / kCell), u(rng), u(rng)}; break;
    }
    const int kind = (i / 4) % 4;
    const float r = kind == 0 ? 0.0f : kind == 1 ? kCell : kCell * unit(rng);
    q.push_back(glm::vec4(x, r));
  }
  return q;
}

struct Gathered {
  uint32_t count = 0;
  uint64_t sum = 0, square_sum = 0;  // of photon index + 1
  bool operator==(const Gathered& o) const {
    return count == o.count && sum == o.sum && square_sum == o.square_sum;
  }
};

std::vector<Gathered> brute_force(const std::vector<glm::vec3>& photons,
                                  const std::vector<glm::vec4>& queries) {
  std::vector<Gathered> out(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    const glm::vec3 x(queries[i]);
    const float r2 = queries[i].w * queries[i].w;
    for (uint64_t j = 0; j < photons.size(); ++j)
      if (test::distance2(photons[j], x) <= r2) {
        ++out[i].count;
        out[i].sum += j + 1;
        out[i].square_sum += (j + 1) * (j + 1);
      }
  }
  return out;
}

struct GridConfig {
  float inv_cell;
  uint32_t mask;
};

TEST(PhotonGrid, GatherEqualsBruteForce) {
  std::mt19937 rng(23);
  const std::vector<glm::vec3> points = grid_photons(rng);
  const std::vector<glm::vec4> queries = gather_queries(points, rng);
  const std::vector<Gathered> want = brute_force(points, queries);
  std::vector<dev::Photon> photons(points.size(), dev::Photon{});
  for (size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a) photons[i].p[a] = points[i][a];

  cl::Context& ctx = test::device_context();
  const uint32_t n = static_cast<uint32_t>(photons.size());
  const uint32_t count = static_cast<uint32_t>(queries.size());
  cl::Buffer photon_buf = cl::Buffer::from_vector(ctx, photons);
  cl::Buffer query_buf = cl::Buffer::from_vector(ctx, queries);
  cl::Buffer next(ctx, n * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "next");
  cl::Buffer counts(ctx, count * sizeof(uint32_t), CL_MEM_WRITE_ONLY, nullptr, "counts");
  cl::Buffer sums(ctx, count * sizeof(uint64_t), CL_MEM_WRITE_ONLY, nullptr, "sums");
  cl::Buffer square_sums(ctx, count * sizeof(uint64_t), CL_MEM_WRITE_ONLY, nullptr, "square sums");
  cl::Kernel insert(photon_map_program(), "grid_insert_photons");
  cl::Kernel gather(photon_map_program(), "grid_gather");

  // Cells of side 0.25 into 256 buckets (most shared by many cells) and into 65536 (as
  // the renderer sizes them for 20 000 photons); and cells of side 0.3, whose boundaries
  // fall between floats.
  for (const GridConfig& grid : {GridConfig{1.0f / kCell, 255}, GridConfig{1.0f / kCell, 65535},
                                 GridConfig{1.0f / 0.3f, 255}}) {
    SCOPED_TRACE("inv_cell " + std::to_string(grid.inv_cell) + ", mask " + std::to_string(grid.mask));
    cl::Buffer heads(ctx, (size_t(grid.mask) + 1) * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "heads");
    heads.fill_zero();
    insert.args(0, photon_buf, n, grid.inv_cell, grid.mask, heads, next);
    insert.launch(ctx, n);

    // Every photon on exactly one bucket's list.
    const std::vector<uint32_t> head = heads.read_vector<uint32_t>(size_t(grid.mask) + 1);
    const std::vector<uint32_t> link = next.read_vector<uint32_t>(n);
    std::vector<uint32_t> visits(n, 0);
    size_t walked = 0;
    for (uint32_t e : head)
      for (; e != 0 && e <= n && walked <= n; e = link[e - 1], ++walked) ++visits[e - 1];
    EXPECT_EQ(walked, n) << "list entries (a cycle, or an entry past the photons)";
    EXPECT_EQ(std::count(visits.begin(), visits.end(), 1u), std::ptrdiff_t(n)) << "photons listed once";

    gather.args(0, photon_buf, heads, next, grid.inv_cell, grid.mask, query_buf, count, counts,
                sums, square_sums);
    gather.launch(ctx, count);
    const std::vector<uint32_t> got_count = counts.read_vector<uint32_t>(count);
    const std::vector<uint64_t> got_sum = sums.read_vector<uint64_t>(count);
    const std::vector<uint64_t> got_square = square_sums.read_vector<uint64_t>(count);
    int failures = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const Gathered got{got_count[i], got_sum[i], got_square[i]};
      if (!(got == want[i]) && ++failures <= 5)
        ADD_FAILURE() << "query (" << queries[i].x << ", " << queries[i].y << ", " << queries[i].z
                      << ") r=" << queries[i].w << ": " << got.count << " photons, brute force "
                      << want[i].count << " (index sums " << got.sum << ", " << want[i].sum << ")";
    }
    EXPECT_EQ(failures, 0) << "of " << count << " gathers";
  }
}

}  // namespace
}  // namespace clpt::photon_map_test
