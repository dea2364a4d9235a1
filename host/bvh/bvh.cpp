// Binned SAH BVH build (Wald 2007), top levels built in parallel, depth-bounded.
//
// Every triangle becomes a 32-byte Prim (its box and original index) and the build
// partitions the Prim array in place, so the hot loops stream through memory. A node's
// box and centroid box are computed by its parent (from the bins and the partition pass),
// so each node costs one binning pass and one partition pass over its triangles.
// Centroids are box centres, kept doubled (lo + hi) to save a multiply.
//
// The upper levels fork: the second child is built on a new thread into its own node
// vector, which is appended after the first (interior offsets shifted by the append
// position; leaf offsets index the shared Prim array and need no change). The result does
// not depend on the number of threads.
#include "bvh/bvh.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <string>
#include <thread>

#include "util/error.h"

namespace clpt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kMaxBins = 64;

struct Prim {
  glm::vec3 lo;
  uint32_t index;
  glm::vec3 hi;
  float pad;
};
static_assert(sizeof(Prim) == 32, "Prim should fill half a cache line");

struct Aabb {
  glm::vec3 lo{kInf};
  glm::vec3 hi{-kInf};

  void grow(const glm::vec3& l, const glm::vec3& h) {
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
  }
  void grow(const glm::vec3& p) { grow(p, p); }
  void grow(const Aabb& b) { grow(b.lo, b.hi); }
  // Half the surface area; 0 for an empty box (SAH weights only need proportionality).
  float half_area() const {
    const glm::vec3 e = hi - lo;
    if (!(e.x >= 0.0f && e.y >= 0.0f && e.z >= 0.0f)) return 0.0f;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// A centroid bin: the box of its triangles and their number. Trivially constructible, so
// that only the bins in use are initialised.
struct Bin {
  glm::vec3 lo, hi;
  uint32_t count;

  void reset() {
    lo = glm::vec3(kInf);
    hi = glm::vec3(-kInf);
    count = 0;
  }
  void add(const glm::vec3& l, const glm::vec3& h) {
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
    ++count;
  }
};

// Levels a subtree of n triangles needs when split at object medians, itself included.
int levels_needed(size_t n, size_t max_leaf) {
  size_t leaves = (n + max_leaf - 1) / max_leaf;
  int levels = 1;
  while (leaves > 1) {
    leaves = (leaves + 1) / 2;
    ++levels;
  }
  return levels;
}

BvhNode make_node(const Aabb& box, int32_t offset, int32_t count) {
  BvhNode node{};
  for (int a = 0; a < 3; ++a) {
    node.bmin[a] = box.lo[a];
    node.bmax[a] = box.hi[a];
  }
  node.offset = offset;
  node.count = count;
  return node;
}

// Runs fn(begin, end) over [0, n) split into one chunk per thread.
template <class Fn>
void parallel_chunks(size_t n, unsigned threads, Fn fn) {
  if (threads <= 1 || n < 65536) {
    fn(size_t(0), n);
    return;
  }
  std::vector<std::future<void>> jobs;
  const size_t chunk = (n + threads - 1) / threads;
  for (unsigned t = 1; t < threads; ++t) {
    const size_t b = std::min(n, t * chunk), e = std::min(n, b + chunk);
    jobs.push_back(std::async(std::launch::async, fn, b, e));
  }
  fn(size_t(0), std::min(n, chunk));
  for (auto& j : jobs) j.get();
}

class Builder {
 public:
  Builder(std::vector<Prim>& prims, const BvhBuildOptions& options, unsigned threads)
      : prims_(prims),
        max_leaf_(static_cast<size_t>(std::max(1, options.max_leaf_size))),
        bins_(std::clamp(options.bins, 2, kMaxBins)) {
    // Fork on the top levels: enough tasks (4 per thread) for the two halves of unequal trees
    // to balance out.
    spawn_levels_ = 0;
    if (threads > 1) {
      while ((1u << spawn_levels_) < threads * 4 && spawn_levels_ < 10) ++spawn_levels_;
    }
  }

  // Builds the subtree of prims [begin, end) whose box and (doubled) centroid box are given,
  // appending it depth-first to out. Returns its depth in levels.
  int build(size_t begin, size_t end, const Aabb& box, const Aabb& cbox, int level,
            std::vector<BvhNode>& out) const {
    const size_t n = end - begin;
    const size_t self = out.size();
    out.push_back(make_node(box, static_cast<int32_t>(begin), static_cast<int32_t>(n)));
    if (n <= max_leaf_ || level >= CLPT_BVH_MAX_DEPTH) return 1;

    Split split;
    if (!find_sah_split(begin, end, cbox, level, split)) median_split(begin, end, cbox, split);
    out[self].count = -split.axis;

    int left_depth, right_depth;
    if (level <= spawn_levels_ && n >= 8192) {
      // The right subtree goes to another thread and its own vector; the left one lands in
      // place. (right_nodes outlives the future, whose destructor waits for the thread.)
      std::vector<BvhNode> right_nodes;
      auto right = std::async(std::launch::async, [&] {
        return build(split.mid, end, split.right, split.right_c, level + 1, right_nodes);
      });
      left_depth = build(begin, split.mid, split.left, split.left_c, level + 1, out);
      right_depth = right.get();
      out[self].offset = static_cast<int32_t>(out.size());
      append(out, right_nodes);
    } else {
      left_depth = build(begin, split.mid, split.left, split.left_c, level + 1, out);
      out[self].offset = static_cast<int32_t>(out.size());
      right_depth = build(split.mid, end, split.right, split.right_c, level + 1, out);
    }
    return 1 + std::max(left_depth, right_depth);
  }

 private:
  struct Split {
    int axis = 0;
    size_t mid = 0;
    Aabb left, right, left_c, right_c;  // boxes and centroid boxes of both sides
  };

  static void append(std::vector<BvhNode>& out, const std::vector<BvhNode>& sub) {
    const int32_t base = static_cast<int32_t>(out.size());
    out.reserve(out.size() + sub.size());
    for (BvhNode node : sub) {
      if (node.count <= 0) node.offset += base;
      out.push_back(node);
    }
  }

  // The best SAH split over the centroid bins of all three axes. False when there is none
  // (all centroids coincide) or when taking it could exceed the depth limit.
  bool find_sah_split(size_t begin, size_t end, const Aabb& cbox, int level, Split& split) const {
    const int nb = bins_;
    const glm::vec3 extent = cbox.hi - cbox.lo;
    glm::vec3 scale;
    bool any_axis = false;
    for (int a = 0; a < 3; ++a) {
      // Slightly under nb / extent so the largest centroid lands in the last bin.
      scale[a] = extent[a] > 0.0f ? float(nb) * (1.0f - 1e-5f) / extent[a] : 0.0f;
      any_axis = any_axis || extent[a] > 0.0f;
    }
    if (!any_axis) return false;

    Bin bins[3][kMaxBins];  // only the first nb of each axis are used and initialised
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < nb; ++b) bins[a][b].reset();
    const glm::vec3 clo = cbox.lo;
    const float last = float(nb - 1);
    for (size_t i = begin; i < end; ++i) {
      const Prim& p = prims_[i];
      const glm::vec3 c = p.lo + p.hi;
      for (int a = 0; a < 3; ++a) {
        bins[a][bin_of(c[a], clo[a], scale[a], last)].add(p.lo, p.hi);
      }
    }

    float best_cost = kInf;
    int best_axis = -1, best_bin = 0;
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      // right_cost[s]: area * count of bins [s, nb).
      float right_cost[kMaxBins];
      Aabb acc;
      uint32_t count = 0;
      for (int s = nb - 1; s >= 1; --s) {
        acc.grow(bins[a][s].lo, bins[a][s].hi);
        count += bins[a][s].count;
        right_cost[s] = count ? acc.half_area() * float(count) : kInf;
      }
      acc = Aabb();
      count = 0;
      for (int s = 1; s < nb; ++s) {
        acc.grow(bins[a][s - 1].lo, bins[a][s - 1].hi);
        count += bins[a][s - 1].count;
        if (count == 0) continue;
        const float cost = acc.half_area() * float(count) + right_cost[s];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = a;
          best_bin = s;
        }
      }
    }
    if (best_axis < 0) return false;  // only reachable with non-finite coordinates

    const int a = best_axis;
    size_t left_count = 0;
    for (int s = 0; s < best_bin; ++s) left_count += bins[a][s].count;
    const size_t n = end - begin;
    if (level + levels_needed(std::max(left_count, n - left_count), max_leaf_) >
        CLPT_BVH_MAX_DEPTH)
      return false;

    split.axis = a;
    split.left = split.right = split.left_c = split.right_c = Aabb();
    for (int s = 0; s < nb; ++s) (s < best_bin ? split.left : split.right).grow(bins[a][s].lo, bins[a][s].hi);

    // In-place partition (Hoare), testing each prim once and growing the centroid boxes.
    size_t i = begin, j = end;
    const float lo = clo[a], k = scale[a];
    auto goes_left = [&](const Prim& p) { return bin_of(p.lo[a] + p.hi[a], lo, k, last) < best_bin; };
    for (;;) {
      while (i < j && goes_left(prims_[i])) {
        split.left_c.grow(prims_[i].lo + prims_[i].hi);
        ++i;
      }
      while (i < j && !goes_left(prims_[j - 1])) {
        --j;
        split.right_c.grow(prims_[j].lo + prims_[j].hi);
      }
      if (i >= j) break;
      --j;
      std::swap(prims_[i], prims_[j]);
      split.left_c.grow(prims_[i].lo + prims_[i].hi);
      split.right_c.grow(prims_[j].lo + prims_[j].hi);
      ++i;
    }
    split.mid = i;
    return i > begin && i < end;  // holds by construction; checked against NaN surprises
  }

  static int bin_of(float c, float lo, float scale, float last) {
    float f = (c - lo) * scale;
    f = f > 0.0f ? f : 0.0f;  // also maps NaN to bin 0
    f = f < last ? f : last;
    return static_cast<int>(f);
  }

  // Splits at the object median along the widest centroid axis (at the middle of the
  // current order when all centroids coincide). Children then need one level less than
  // their parent, which keeps every subtree within the depth limit.
  void median_split(size_t begin, size_t end, const Aabb& cbox, Split& split) const {
    const glm::vec3 e = cbox.hi - cbox.lo;
    int axis = 0;
    if (e.y > e[axis]) axis = 1;
    if (e.z > e[axis]) axis = 2;
    const size_t mid = begin + (end - begin) / 2;
    if (e[axis] > 0.0f) {
      std::nth_element(prims_.begin() + begin, prims_.begin() + mid, prims_.begin() + end,
                       [axis](const Prim& x, const Prim& y) {
                         return x.lo[axis] + x.hi[axis] < y.lo[axis] + y.hi[axis];
                       });
    }
    split.axis = axis;
    split.mid = mid;
    split.left = split.right = split.left_c = split.right_c = Aabb();
    for (size_t i = begin; i < end; ++i) {
      const Prim& p = prims_[i];
      Aabb& box = i < mid ? split.left : split.right;
      Aabb& cb = i < mid ? split.left_c : split.right_c;
      box.grow(p.lo, p.hi);
      cb.grow(p.lo + p.hi);
    }
  }

  std::vector<Prim>& prims_;
  size_t max_leaf_;
  int bins_;
  int spawn_levels_ = 0;
};

}  // namespace

Bvh build_bvh(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
              const BvhBuildOptions& options) {
  Bvh bvh;
  const size_t n = triangles.size();
  if (n > size_t(std::numeric_limits<int32_t>::max()))
    throw Error(ExitCode::BadInput, "too many triangles for the BVH: " + std::to_string(n) +
                                        " (at most 2147483647)");
  if (n == 0) {
    // An empty box no ray enters; see bvh.h.
    bvh.nodes.push_back(make_node(Aabb(), 0, 1));
    bvh.depth = 1;
    bvh.wide = collapse_bvh4(bvh.nodes, &bvh.wide_depth);
    return bvh;
  }

  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  const size_t num_vertices = positions.size();
  std::vector<Prim> prims(n);
  std::vector<Aabb> chunk_box(threads), chunk_cbox(threads);
  std::vector<size_t> bad(threads, SIZE_MAX);
  const size_t chunk = (n + threads - 1) / threads;
  parallel_chunks(n, threads, [&](size_t b, size_t e) {
    const size_t slot = b / chunk;
    Aabb box, cbox;
    for (size_t i = b; i < e; ++i) {
      const glm::uvec3 t = triangles[i];
      if (t.x >= num_vertices || t.y >= num_vertices || t.z >= num_vertices) {
        bad[slot] = std::min(bad[slot], i);
        continue;
      }
      const glm::vec3 &p0 = positions[t.x], &p1 = positions[t.y], &p2 = positions[t.z];
      Prim& p = prims[i];
      p.lo = glm::min(p0, glm::min(p1, p2));
      p.hi = glm::max(p0, glm::max(p1, p2));
      p.index = static_cast<uint32_t>(i);
      p.pad = 0.0f;
      box.grow(p.lo, p.hi);
      cbox.grow(p.lo + p.hi);
    }
    chunk_box[slot] = box;
    chunk_cbox[slot] = cbox;
  });
  const size_t first_bad = *std::min_element(bad.begin(), bad.end());
  if (first_bad != SIZE_MAX) {
    const glm::uvec3 t = triangles[first_bad];
    throw Error(ExitCode::BadInput,
                "triangle " + std::to_string(first_bad) + " has vertex indices (" +
                    std::to_string(t.x) + ", " + std::to_string(t.y) + ", " + std::to_string(t.z) +
                    ") but there are only " + std::to_string(num_vertices) + " vertices");
  }
  Aabb box, cbox;
  for (unsigned t = 0; t < threads; ++t) {
    box.grow(chunk_box[t]);
    cbox.grow(chunk_cbox[t]);
  }

  Builder builder(prims, options, threads);
  bvh.nodes.reserve(2 * n / std::max(1, options.max_leaf_size) + 16);
  bvh.depth = builder.build(0, n, box, cbox, 1, bvh.nodes);

  bvh.triangle_order.resize(n);
  for (size_t i = 0; i < n; ++i) bvh.triangle_order[i] = prims[i].index;
  bvh.wide = collapse_bvh4(bvh.nodes, &bvh.wide_depth);
  // The kernels' stack keeps a leaf as its node's index << 2 under a flag bit.
  if (bvh.wide.size() > (size_t(1) << 29))
    throw Error(ExitCode::BadInput, "too many BVH nodes: " + std::to_string(bvh.wide.size()) +
                                        " 4-wide nodes (at most 536870912)");
  return bvh;
}

std::vector<dev::BvhNode4> collapse_bvh4(const std::vector<BvhNode>& nodes, int* depth) {
  std::vector<dev::BvhNode4> wide;
  *depth = 0;
  if (nodes.empty()) return wide;
  auto area = [&](uint32_t i) {
    const BvhNode& n = nodes[i];
    const float dx = n.bmax[0] - n.bmin[0], dy = n.bmax[1] - n.bmin[1], dz = n.bmax[2] - n.bmin[2];
    return dx * dy + dy * dz + dz * dx;
  };
  auto empty_node = [] {
    dev::BvhNode4 w{};
    for (int k = 0; k < 4; ++k) {
      w.bmin_x[k] = w.bmin_y[k] = w.bmin_z[k] = std::numeric_limits<float>::infinity();
      w.bmax_x[k] = w.bmax_y[k] = w.bmax_z[k] = -std::numeric_limits<float>::infinity();
      w.child[k] = -1;
      w.count[k] = 0;
    }
    return w;
  };
  struct Todo {
    uint32_t binary;  // the binary node whose subtree this wide node holds
    uint32_t wide;    // its index in `wide`
    int level;        // 1 for the root
  };
  std::vector<Todo> todo = {{0, 0, 1}};
  wide.push_back(empty_node());
  while (!todo.empty()) {
    const Todo t = todo.back();
    todo.pop_back();
    *depth = std::max(*depth, t.level);
    uint32_t kids[4];
    int count = 0;
    const BvhNode& b = nodes[t.binary];
    if (b.count > 0) {
      kids[count++] = t.binary;  // a root that is a leaf
    } else {
      kids[count++] = t.binary + 1;
      kids[count++] = uint32_t(b.offset);
    }
    // The binary node's inner children are opened first, so that every inner child the wide
    // node keeps lies at least two binary levels below it; then the largest by area.
    bool first_level[4] = {b.count <= 0, b.count <= 0, false, false};
    while (count < 4) {
      int open = -1;
      for (int k = 0; k < count; ++k) {
        if (nodes[kids[k]].count > 0) continue;
        if (open < 0 || (first_level[k] && !first_level[open]) ||
            (first_level[k] == first_level[open] && area(kids[k]) > area(kids[open])))
          open = k;
      }
      if (open < 0) break;
      const uint32_t inner = kids[open];
      for (int k = count; k > open + 1; --k) first_level[k] = first_level[k - 1];
      first_level[open] = first_level[open + 1] = false;
      kids[open] = inner + 1;  // its children, in the binary order
      for (int k = count; k > open + 1; --k) kids[k] = kids[k - 1];
      kids[open + 1] = uint32_t(nodes[inner].offset);
      ++count;
    }
    for (int k = 0; k < count; ++k) {
      const BvhNode& c = nodes[kids[k]];
      // The empty scene's phantom leaf (an empty box, see bvh.h) becomes an empty slot: a ray
      // with a NaN origin passes every box test, and must still find no triangle to read.
      if (c.count > 0 && !(c.bmin[0] <= c.bmax[0])) continue;
      dev::BvhNode4& w = wide[t.wide];
      w.bmin_x[k] = c.bmin[0];
      w.bmin_y[k] = c.bmin[1];
      w.bmin_z[k] = c.bmin[2];
      w.bmax_x[k] = c.bmax[0];
      w.bmax_y[k] = c.bmax[1];
      w.bmax_z[k] = c.bmax[2];
      if (c.count > 0) {
        w.child[k] = ~c.offset;
        w.count[k] = uint32_t(c.count);
      } else {
        const uint32_t index = uint32_t(wide.size());
        w.child[k] = int32_t(index);
        w.count[k] = 0;
        wide.push_back(empty_node());  // invalidates w
        todo.push_back({kids[k], index, t.level + 1});
      }
    }
  }
  return wide;
}

std::vector<LeafRange> wide_leaves(const std::vector<dev::BvhNode4>& wide) {
  std::vector<LeafRange> leaves;
  for (const dev::BvhNode4& node : wide)
    for (int k = 0; k < 4; ++k)
      if (node.child[k] < 0 && node.count[k] > 0) leaves.push_back({uint32_t(~node.child[k]), node.count[k]});
  std::sort(leaves.begin(), leaves.end(),
            [](const LeafRange& a, const LeafRange& b) { return a.first < b.first; });
  return leaves;
}

void leaf_lanes(const LeafRange& leaf, const dev::Triangle* triangles, const dev::Vertex* vertices,
                float* out) {
  for (uint32_t j = 0; j < leaf.count; j += 4) {
    const uint32_t m = std::min<uint32_t>(leaf.count - j, 4);
    float* group = out + 9 * size_t(j);
    for (uint32_t l = 0; l < m; ++l) {
      const dev::Triangle& t = triangles[leaf.first + j + l];
      for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) group[(3 * v + a) * m + l] = vertices[t.v[v]].p[a];
    }
  }
}

std::vector<float> triangle_lanes(const std::vector<dev::BvhNode4>& wide,
                                  const std::vector<dev::Triangle>& triangles,
                                  const std::vector<dev::Vertex>& vertices) {
  std::vector<float> lanes(9 * triangles.size() + kTriangleLanesPadding, 0.0f);
  for (const LeafRange& leaf : wide_leaves(wide))
    leaf_lanes(leaf, triangles.data(), vertices.data(), lanes.data() + 9 * size_t(leaf.first));
  return lanes;
}
}  // namespace clpt
