// Vertex connection and merging (--integrator vcm, kernels/integrators/vcm.cl; Georgiev et
// al. 2012, docs/concepts/vcm.md). Per sample index one pass with its own merge radius
// r_i = r_0 (i + 1)^((alpha - 1) / 2) (Knaus and Zwicker 2011's rate, as SmallVCM), and per
// tile of pixel indices three kernels: vcm_light traces K light subpaths per pixel index
// (--vcm-light-paths K, or auto: 1, 2 or 4 by the first passes' measured efficiency,
// integrators/vcm_pilot.h; camera connections splatted, vertices stored), vcm_grid_count and vcm_grid_fill sort the
// tile's vertices by the bucket of their cell (cells 2r wide; the host sums the counts into
// bucket starts between them), vcm_camera traces one camera subpath per pixel that connects
// to its own (first) light subpath and merges with the whole tile's (at its first non-delta vertex,
// or with --vcm-merge all at every one: VcmConfig::merge_first). Tiles are as large as the
// memory budget allows (vertices, grid points and buckets); eta = pi r^2 (light paths of the tile)
// so a merge's normalisation and its MIS weights are right for any tile size.
// With --vcm-shrink pixel each pixel keeps its own (r, N), shrunk after each pass as sppm's
// by the merges its first merging vertex found, in two buffers that swap after the pass; the
// light subpaths are traced with the pass's radius and their vertices carry EtaSlopes
// (kernels/integrators/stages/vertex_mis.cl) for the pixels' own.
// Like bdpt, its film has splats: no per-pixel variance, sums not bit-reproducible.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "integrators/integrator.h"
#include "shared/vcm_types.h"

namespace clpt {

class VertexConnectionMerging final : public Integrator {
 public:
  // subpaths: bdpt's settings its light subpaths follow (--bdpt-lvc, --bdpt-memory). The
  // first radius (config.radius, 0: its default) is resolved by first_radius.
  VertexConnectionMerging(const cl::Context& ctx, const SceneBuffers& scene, const VcmConfig& config,
                          const BdptConfig& subpaths, const SceneScale& scale);
  const char* name() const override { return "vcm"; }
  void warm_up(const dev::RenderParams& params, Film& film) override;
  void render_pass(const dev::RenderParams& params, Film& film) override;
  const cl::BuildInfo& build_info() const override { return program_.build_info(); }
  uint64_t connections() const override;
  VcmStats vcm_stats() const override;
  // "merged": the radiance merging added, per pixel, over spp passes.
  std::vector<NamedChannel> layers(uint64_t spp) const override;

  // Light vertices stored per light path: one per bounce (at least 1).
  static uint32_t vertex_capacity(uint32_t max_depth) { return max_depth > 1 ? max_depth : 1; }
  // Paths per tile within a budget: each path's vertices with their slopes, their grid points
  // and the grid's buckets (at most two per slot), and its vertex count.
  static size_t tile_paths(size_t budget_bytes, uint32_t capacity, size_t pixels);
  // The first pass's merge radius: `given`, or default_merge_radius times 0.75 with per-pixel
  // radii (`pixel`) and 0.5 without, held within the bounds; a given radius outside [1e-6,
  // 0.1] times the scene's diagonal is a usage error.
  static float first_radius(float given, const SceneScale& scale, bool pixel);
  // Pass i's merge radius.
  static float radius(float r0, float alpha, uint32_t pass);
  // The pass's VcmParams for a tile of `paths` light paths, `k` per pixel (0: c's).
  static dev::VcmParams pass_params(const VcmConfig& c, uint32_t mis, float radius, uint32_t paths,
                                    uint32_t mask, uint32_t k = 0);

 private:
  // Uploads the pass's parameters; buffers sized for the film, the light vertex capacity and
  // k light subpaths per pixel (during auto's pilot: for its largest candidate, so that the
  // pilot's passes do not reallocate).
  void prepare(const dev::RenderParams& params, Film& film, uint32_t k);
  // Pixel indices per tile at k light subpaths each, within --bdpt-memory.
  size_t tile_pixels(uint32_t k, uint32_t capacity, size_t pixels) const {
    return tile_paths(subpaths_.memory_bytes / k, capacity, pixels);
  }
  // Uploads the VcmParams of a tile of `paths` light paths at radius r (pass_params, with the
  // light vertex capacity, --bdpt-lvc and the pass's K and first light sample index).
  void write_vcm_params(uint32_t mis, float r, uint32_t paths, uint32_t light_sample);
  void launch_tile(const dev::RenderParams& p, uint32_t sample, uint32_t first, uint32_t count,
                   float r, Film& film);
  // One pass of sample index `sample`, every tile.
  void render_sample(const dev::RenderParams& params, uint32_t sample, Film& film);
  // The next pass's K: the given one, 1 before the pilot, the pilot's next candidate, or its
  // choice.
  uint32_t pass_k(const Film& film);
  // The film's sums and splats at the pilot's pixels (RGB), read back.
  std::vector<float> pilot_film(Film& film) const;

  const cl::Context& ctx_;
  VcmConfig config_;  // its radius resolved
  BdptConfig subpaths_;
  cl::Program program_;
  cl::Kernel light_kernel_, count_kernel_, fill_kernel_, camera_kernel_;
  cl::Buffer params_, vcm_params_;
  cl::Buffer vertices_, vertex_counts_;
  cl::Buffer slopes_;  // per slot: its vertex's EtaSlopes (written with per-pixel radii)
  // The merge grid, cell-sorted (spatial/hash_grid.cl): per bucket its count and then its
  // first point (buckets + 1 entries), the fill's cursors, the points in bucket order.
  cl::Buffer starts_, cursor_, points_;
  std::vector<uint32_t> bucket_starts_;  // the host's exclusive sum of the counts
  cl::Buffer cache_, cache_count_;  // light vertex caching: the tile's stored vertices' slots
  // Per pixel index, allocated with the first pass.
  cl::Buffer connection_counts_, stored_counts_, merge_counts_, merge_sum_;
  // Per pixel (r, N) with --vcm-shrink pixel: this pass's and the next's (swapped after a pass).
  cl::Buffer radii_, next_radii_;
  size_t pixels_ = 0;
  uint32_t width_ = 0;
  uint32_t capacity_ = 0;
  size_t tile_ = 0;         // pixel indices per tile at the pass's K
  uint32_t mask_ = 0;       // the pass's grid buckets - 1
  size_t slots_ = 0;        // light vertex slots allocated
  uint32_t k_ = 1;          // the pass's light subpaths per pixel
  uint32_t light_base_ = 0;  // auto: the light subpaths each pixel traced in the passes before
  std::optional<LightPathPilot> pilot_;  // auto: the first passes' measurement
  uint32_t chosen_k_ = 0;  // auto: K once settled (the pilot's choice, or 1 for a short render)
  std::vector<float> pilot_before_;  // the pilot's film before the pass it times
  bool pixel_radius_ = false;  // per-pixel radii in use (config_'s, with the box filter)
  cl_uint light_arg_ = 0, camera_arg_ = 0;
  VcmStats stats_;
};

}  // namespace clpt
