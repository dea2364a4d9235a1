// Left-balanced kd-tree build (median splits on the axis of largest extent, heap order)
// and its k-nearest-neighbour and radius queries. See kdtree.h for the layout.
//
// Build: the photons are copied into 16-byte KdNodes (a work array). A subtree is a heap
// node plus a range of the work array; its left subtree's size is fixed by the heap shape
// (subtree_size below), so the median position is known before selecting: nth_element puts
// the photon of that rank on the chosen axis in place, smaller-or-equal ones before it and
// greater-or-equal ones after, and those two ranges become the children. Each level costs
// O(n) (bounds plus selection), so the build is O(n log n). Subtrees own disjoint ranges of
// the work array and disjoint heap slots, so the top levels fork onto other threads.
//
// Queries: a depth-first walk, nearer child first, examining each node's photon on the way
// down, with an explicit stack of far children and their cells' offsets from the query
// point (Pending below; a far child's bound is rechecked when popped because the kNN radius
// may have shrunk meanwhile). Written as the OpenCL C port will be: fixed arrays, no
// recursion, no allocation but the caller's output vector.
#include "photon/kdtree.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <string>
#include <thread>

#include "util/error.h"

namespace clpt {
namespace {

struct Range {
  uint32_t node;   // heap slot
  uint32_t begin;  // work-array range [begin, end)
  uint32_t end;
};

// Number of nodes in the subtree rooted at heap slot i of a complete tree of n nodes.
uint32_t subtree_size(uint64_t i, uint64_t n) {
  uint64_t size = 0;
  for (uint64_t first = i, last = i; first < n; first = 2 * first + 1, last = 2 * last + 2)
    size += std::min(last, n - 1) - first + 1;
  return static_cast<uint32_t>(size);
}

inline float distance2(const glm::vec3& p, const KdNode& node) {
  const float dx = p.x - node.pos[0];
  const float dy = p.y - node.pos[1];
  const float dz = p.z - node.pos[2];
  return dx * dx + dy * dy + dz * dz;
}

class Builder {
 public:
  Builder(std::vector<KdNode>& work, std::vector<KdNode>& nodes)
      : work_(work), nodes_(nodes), n_(static_cast<uint32_t>(nodes.size())) {}

  // Builds `r` and everything below it; the first `fork_levels` levels hand their right
  // subtree to another thread.
  void build(Range r, int fork_levels) {
    if (fork_levels > 0 && r.end - r.begin >= kMinForkSize) {
      Range left, right;
      if (!split(r, left, right)) return;
      if (right.end > right.begin) {
        auto job = std::async(std::launch::async, [&] { build(right, fork_levels - 1); });
        build(left, fork_levels - 1);
        job.get();
      } else {
        build(left, fork_levels - 1);
      }
      return;
    }
    // Serial: an explicit stack of pending subtrees (a subtree of m nodes is
    // floor(log2 m) + 1 levels deep, so at most one pending entry per level).
    Range stack[kKdMaxStack + 1];
    int top = 0;
    stack[top++] = r;
    while (top > 0) {
      const Range cur = stack[--top];
      Range left, right;
      if (!split(cur, left, right)) continue;
      if (right.end > right.begin) stack[top++] = right;
      stack[top++] = left;
    }
  }

 private:
  static constexpr uint32_t kMinForkSize = 1u << 15;

  // Places the median of `r` in its heap slot and returns the children's ranges; false
  // for a leaf. A left range is never empty for an interior node; a right one may be.
  bool split(const Range& r, Range& left, Range& right) {
    KdNode* const first = work_.data() + r.begin;
    const uint32_t count = r.end - r.begin;
    if (count == 1) {
      nodes_[r.node] = first[0];
      nodes_[r.node].index_axis = (first[0].index_axis & ~3u) | kKdLeafAxis;
      return false;
    }
    // Axis of largest extent of this subset. Among equal extents (degenerate subsets:
    // coincident photons, photons on a line) the first at or after the node's level mod 3,
    // so coincident photons are split on the three axes in turn: a query's cell bound then
    // reaches their true distance within three levels and the kNN search stops there
    // instead of visiting every copy.
    float lo[3] = {first[0].pos[0], first[0].pos[1], first[0].pos[2]};
    float hi[3] = {lo[0], lo[1], lo[2]};
    for (uint32_t i = 1; i < count; ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], first[i].pos[a]);
        hi[a] = std::max(hi[a], first[i].pos[a]);
      }
    }
    uint32_t level = 0;
    for (uint32_t v = r.node + 1; v > 1; v >>= 1) ++level;
    uint32_t axis = level % 3;
    for (uint32_t j = 1; j < 3; ++j) {
      const uint32_t a = (level + j) % 3;
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    }

    const uint32_t left_count = subtree_size(2ull * r.node + 1, n_);
    KdNode* const median = first + left_count;
    std::nth_element(first, median, first + count,
                     [axis](const KdNode& a, const KdNode& b) { return a.pos[axis] < b.pos[axis]; });
    nodes_[r.node] = *median;
    nodes_[r.node].index_axis = (median->index_axis & ~3u) | axis;
    left = {2 * r.node + 1, r.begin, r.begin + left_count};
    right = {2 * r.node + 2, r.begin + left_count + 1, r.end};
    return true;
  }

  std::vector<KdNode>& work_;
  std::vector<KdNode>& nodes_;
  uint32_t n_;
};

// A subtree still to visit, with the offset of its cell from the query point p along each
// axis (0 where p lies within the cell's slab; else p's signed distance to the slab's nearer
// plane). Arya and Mount's incremental distance (1993): the cell's squared distance to p is
// the sum of the squared offsets, a tighter bound than Jensen's distance to the last
// splitting plane alone (which is that one offset), and it keeps queries far from the
// photons (unbounded kNN outside the cloud) from visiting most of the tree. 16 bytes: one
// float4 on the device. Descending to the near child keeps the offsets; the far child
// replaces the split axis's offset with p's distance to the splitting plane.
struct Pending {
  float offset[3];
  uint32_t node;
};
static_assert(sizeof(Pending) == 16, "Pending must stay one float4");

// Summed in the same order as distance2, so by monotone rounding it never exceeds the
// distance2 of a photon in the cell: pruning on it is exact in float.
inline float cell_distance2(const Pending& c) {
  return c.offset[0] * c.offset[0] + c.offset[1] * c.offset[1] + c.offset[2] * c.offset[2];
}

// Max-heap on distance2 over heap[0, size): the k best candidates, the worst at heap[0].
void sift_up(KdNeighbor* heap, uint32_t i) {
  while (i > 0) {
    const uint32_t parent = (i - 1) / 2;
    if (heap[parent].distance2 >= heap[i].distance2) break;
    std::swap(heap[parent], heap[i]);
    i = parent;
  }
}

void sift_down(KdNeighbor* heap, uint32_t i, uint32_t size) {
  for (;;) {
    const uint32_t l = 2 * i + 1;
    if (l >= size) break;
    uint32_t c = l;
    if (l + 1 < size && heap[l + 1].distance2 > heap[l].distance2) c = l + 1;
    if (heap[c].distance2 <= heap[i].distance2) break;
    std::swap(heap[c], heap[i]);
    i = c;
  }
}

}  // namespace

KdTree build_kdtree(const std::vector<glm::vec3>& points) {
  if (points.size() > kKdMaxPoints)
    throw Error(ExitCode::BadInput, "kd-tree: " + std::to_string(points.size()) +
                                        " photons, more than the " + std::to_string(kKdMaxPoints) +
                                        " a tree can index");
  const uint32_t n = static_cast<uint32_t>(points.size());
  std::vector<KdNode> work(n);
  for (uint32_t i = 0; i < n; ++i) {
    const glm::vec3& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(ExitCode::BadInput, "kd-tree: photon " + std::to_string(i) +
                                          " has a non-finite position");
    work[i] = KdNode{{p.x, p.y, p.z}, i << 2};
  }
  KdTree tree;
  tree.nodes.resize(n);
  if (n == 0) return tree;

  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  int fork_levels = 0;
  while ((1u << fork_levels) < threads * 2 && fork_levels < 8) ++fork_levels;
  if (threads == 1) fork_levels = 0;
  Builder(work, tree.nodes).build(Range{0, 0, n}, fork_levels);
  return tree;
}

int KdTree::height() const {
  int h = 0;
  for (size_t level_end = 0; level_end < nodes.size(); level_end = 2 * level_end + 1) ++h;
  return h;
}

size_t KdTree::knn(const glm::vec3& p, size_t k, float max_radius,
                   std::vector<KdNeighbor>& out) const {
  out.clear();
  const uint32_t n = static_cast<uint32_t>(nodes.size());
  if (n == 0 || k == 0 || !(max_radius >= 0.0f)) return 0;
  const uint32_t capacity = static_cast<uint32_t>(std::min<size_t>(k, n));
  out.resize(capacity);
  KdNeighbor* const heap = out.data();
  uint32_t count = 0;
  float r2 = max_radius * max_radius;  // shrinks to the k-th distance once the heap is full
  // A cell may hold a better photon if it reaches within r2, or, once the heap is full, if
  // it reaches closer than the k-th distance: a photon tied with the k-th would not replace
  // it (without this, a million coincident photons would all be visited).
  auto reaches = [&](float bound) { return count < capacity ? bound <= r2 : bound < r2; };

  Pending stack[kKdMaxStack];
  int top = 0;
  Pending cur{{0.0f, 0.0f, 0.0f}, 0};  // the root's cell holds p: no offset
  for (;;) {
    // Descend towards p, examining each node's photon and remembering the far children.
    uint32_t i = cur.node;
    while (i < n) {
      const KdNode& node = nodes[i];
      const float d2 = distance2(p, node);
      if (d2 <= r2) {
        if (count < capacity) {
          heap[count] = {d2, kd_photon_index(node)};
          sift_up(heap, count);
          if (++count == capacity) r2 = heap[0].distance2;
        } else if (d2 < heap[0].distance2) {
          heap[0] = {d2, kd_photon_index(node)};
          sift_down(heap, 0, capacity);
          r2 = heap[0].distance2;
        }
      }
      const uint32_t axis = kd_split_axis(node);
      if (axis == kKdLeafAxis) break;
      const float d = p[axis] - node.pos[axis];
      const uint32_t near = d < 0.0f ? 2 * i + 1 : 2 * i + 2;
      const uint32_t far = d < 0.0f ? 2 * i + 2 : 2 * i + 1;
      if (far < n) {
        Pending f = cur;
        f.offset[axis] = d;
        f.node = far;
        if (reaches(cell_distance2(f))) stack[top++] = f;
      }
      i = near;  // the right child may not exist: the loop ends and the stack is popped
    }
    // The next far subtree that the (possibly shrunk) radius still reaches.
    while (top > 0 && !reaches(cell_distance2(stack[top - 1]))) --top;
    if (top == 0) break;
    cur = stack[--top];
  }

  // Heap sort in place: ascending distance2.
  for (uint32_t end = count; end > 1; --end) {
    std::swap(heap[0], heap[end - 1]);
    sift_down(heap, 0, end - 1);
  }
  out.resize(count);
  return count;
}

size_t KdTree::within(const glm::vec3& p, float radius, std::vector<KdNeighbor>& out) const {
  out.clear();
  const uint32_t n = static_cast<uint32_t>(nodes.size());
  if (n == 0 || !(radius >= 0.0f)) return 0;
  const float r2 = radius * radius;

  Pending stack[kKdMaxStack];
  int top = 0;
  Pending cur{{0.0f, 0.0f, 0.0f}, 0};
  for (;;) {
    uint32_t i = cur.node;
    while (i < n) {
      const KdNode& node = nodes[i];
      const float d2 = distance2(p, node);
      if (d2 <= r2) out.push_back({d2, kd_photon_index(node)});
      const uint32_t axis = kd_split_axis(node);
      if (axis == kKdLeafAxis) break;
      const float d = p[axis] - node.pos[axis];
      const uint32_t near = d < 0.0f ? 2 * i + 1 : 2 * i + 2;
      const uint32_t far = d < 0.0f ? 2 * i + 2 : 2 * i + 1;
      if (far < n) {
        Pending f = cur;
        f.offset[axis] = d;
        f.node = far;
        if (cell_distance2(f) <= r2) stack[top++] = f;
      }
      i = near;
    }
    if (top == 0) break;
    cur = stack[--top];
  }
  return out.size();
}

}  // namespace clpt
