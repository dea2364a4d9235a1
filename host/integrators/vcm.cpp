#include "integrators/vcm.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>

#include "cl/programs.h"
#include "shared/bdpt_types.h"
#include "shared/photon_types.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

VertexConnectionMerging::VertexConnectionMerging(const cl::Context& ctx, const SceneBuffers& scene,
                                                 const VcmConfig& config, const BdptConfig& subpaths,
                                                 const SceneScale& scale)
    : ctx_(ctx),
      config_(config),
      subpaths_(subpaths),
      program_(ctx, programs::kVcm),
      light_kernel_(program_, "vcm_light"),
      count_kernel_(program_, "vcm_grid_count"),
      fill_kernel_(program_, "vcm_grid_fill"),
      camera_kernel_(program_, "vcm_camera"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      vcm_params_(ctx, sizeof(dev::VcmParams), CL_MEM_READ_ONLY, nullptr, "VCM parameters"),
      cache_count_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "VCM light vertex cache count") {
  config_.radius = first_radius(config.radius, scale, config.pixel_radius);
  // light_per_pixel 0 is auto (pass_k).
  if (!(config_.radius > 0.0f) || !std::isfinite(config_.radius))
    throw Error(ExitCode::Usage, "vcm needs a positive merge radius");
  light_arg_ = scene.bind(light_kernel_, 0);
  camera_arg_ = scene.bind(camera_kernel_, 0);
}

size_t VertexConnectionMerging::tile_paths(size_t budget_bytes, uint32_t capacity, size_t pixels) {
  // Per slot: the vertex and its slopes, its grid point, its cache entry and up to two
  // buckets' start and cursor.
  const size_t per_path =
      size_t(capacity) * (sizeof(dev::PathVertex) + 2 * sizeof(float) + sizeof(dev::GridPoint) +
                          5 * sizeof(uint32_t)) +
      sizeof(uint32_t);
  return std::clamp<size_t>(budget_bytes / per_path, 1, std::max<size_t>(pixels, 1));
}

float VertexConnectionMerging::first_radius(float given, const SceneScale& scale, bool pixel) {
  // One pixel footprint at the scene's centre, half sppm's default radius, when the radius
  // shrinks per pass (the --vcm-radius sweep in docs/BENCHMARKS.md, session 11); sppm's two
  // when each pixel's shrinks by its own merges (session 33's sweep, merging at the first
  // vertex alone; 1.5 had been best merging at every vertex). A radius near the scene's size merges every
  // light vertex at every camera vertex, and one below float resolution at the scene's scale
  // puts them all in one saturated grid cell: either is a render that does not end. 10 % and
  // 1e-6 of the diagonal bound it. The default is held inside the bounds: at a tiny
  // resolution (8x8) a footprint is above 10 %, and a radius nobody asked for is no usage error.
  const float lo = 1e-6f * scale.diagonal, hi = 0.1f * scale.diagonal;
  if (!(given > 0.0f))
    return std::clamp((pixel ? 1.0f : 0.5f) * default_merge_radius(scale), lo, hi);
  if (!(given <= hi && given >= lo))
    throw Error(ExitCode::Usage, "--vcm-radius " + std::to_string(given) +
                                     " is outside [1e-6, 0.1] times the scene's diagonal (" +
                                     std::to_string(scale.diagonal) + ")");
  return given;
}

float VertexConnectionMerging::radius(float r0, float alpha, uint32_t pass) {
  return r0 * static_cast<float>(std::pow(double(pass) + 1.0, 0.5 * (double(alpha) - 1.0)));
}

dev::VcmParams VertexConnectionMerging::pass_params(const VcmConfig& c, uint32_t mis, float r,
                                                    uint32_t paths, uint32_t mask, uint32_t k) {
  const auto heuristic = [mis](double x) { return float(mis == dev::MIS_BALANCE ? x : x * x); };
  const double eta = 3.14159265358979323846 * double(r) * double(r) * double(std::max(paths, 1u));
  dev::VcmParams v{};
  v.mode = c.mode;
  v.radius = r;
  v.mis_vm = dev::vcm_mode_merges(c.mode) ? heuristic(eta) : 0.0f;
  v.mis_vc = dev::vcm_mode_connects(c.mode) ? heuristic(1.0 / eta) : 0.0f;
  v.vm_normalization = float(1.0 / eta);
  v.inv_cell = 1.0f / (2.0f * r);
  v.mask = mask;
  v.light_paths = paths;
  v.alpha = c.alpha;
  v.merge_first = c.merge_first ? 1u : 0u;
  v.light_per_pixel = std::max(k ? k : c.light_per_pixel, 1u);
  v.eta_per_r2 = float(3.14159265358979323846 * double(std::max(paths, 1u)));
  return v;
}

void VertexConnectionMerging::prepare(const dev::RenderParams& params, Film& film, uint32_t k) {
  if (!film.splats()) throw Error(ExitCode::Usage, "vcm needs a film with splats");
  // Per-pixel radii only where every contribution lands in one pixel (the command line
  // refuses them with another filter; settings made in code fall back to the pass rule).
  pixel_radius_ = config_.pixel_radius && dev::vcm_mode_merges(config_.mode) &&
                  params.filter == dev::FILTER_BOX && params.filter_radius == 0.5f;
  const uint32_t capacity = vertex_capacity(params.max_depth);
  const size_t pixels = film.pixels();
  if (pixels_ != pixels) {
    const auto counts = [&](const char* what) {
      cl::Buffer b(ctx_, pixels * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, what);
      b.fill_zero();
      return b;
    };
    connection_counts_ = counts("VCM connection counts");
    stored_counts_ = counts("VCM light vertex counts per pixel");
    merge_counts_ = counts("VCM merge counts");
    merge_sum_ = cl::Buffer(ctx_, pixels * 4 * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                            "VCM merged radiance");
    merge_sum_.fill_zero();
    // Every pixel starts at the first radius, with no merges behind it.
    const std::vector<float> start = [&] {
      std::vector<float> rn(2 * pixels, 0.0f);
      for (size_t i = 0; i < pixels; ++i) rn[2 * i] = config_.radius;
      return rn;
    }();
    radii_ = cl::Buffer(ctx_, pixels * 2 * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                        "VCM per-pixel radii");
    next_radii_ = cl::Buffer(ctx_, pixels * 2 * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                             "VCM per-pixel radii, next pass");
    radii_.write(start.data(), start.size() * sizeof(float));
    next_radii_.write(start.data(), start.size() * sizeof(float));
    pixels_ = pixels;
    width_ = film.width();
  }
  // A tile's pixel indices each trace k light paths: the budget divides by them. The pilot's
  // passes share the buffers of its largest candidate's tiles.
  k_ = k;
  tile_ = tile_pixels(k, capacity, pixels);
  size_t paths = tile_ * k;
  if (pilot_ && !pilot_->done())
    for (uint32_t c : LightPathPilot::kCandidates)
      paths = std::max(paths, tile_pixels(c, capacity, pixels) * c);
  // The grid's buckets: a power of two, at least the tile's slots (so the pass's grid is the
  // same whatever the buffers' size).
  size_t buckets = 1024;
  while (buckets < tile_ * k * capacity) buckets *= 2;
  mask_ = static_cast<uint32_t>(buckets - 1);
  bucket_starts_.resize(buckets + 1);
  if (capacity != capacity_ || paths * capacity != slots_) {
    const size_t slots = paths * capacity;
    vertices_ = cl::Buffer(ctx_, slots * sizeof(dev::PathVertex), CL_MEM_READ_WRITE, nullptr,
                           "VCM light vertices");
    vertex_counts_ = cl::Buffer(ctx_, paths * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                                "VCM light vertex counts");
    slopes_ = cl::Buffer(ctx_, slots * 2 * sizeof(float), CL_MEM_READ_WRITE, nullptr,
                         "VCM light vertex slopes");
    points_ = cl::Buffer(ctx_, slots * sizeof(dev::GridPoint), CL_MEM_READ_WRITE, nullptr,
                         "VCM grid points");
    cache_ = cl::Buffer(ctx_, slots * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                        "VCM light vertex cache");
    size_t most = 1024;
    while (most < slots) most *= 2;
    starts_ = cl::Buffer(ctx_, (most + 1) * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                         "VCM grid bucket starts");
    cursor_ = cl::Buffer(ctx_, most * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                         "VCM grid cursors");
    capacity_ = capacity;
    slots_ = slots;
  }
  stats_.device_bytes = vertices_.size() + slopes_.size() + vertex_counts_.size() + points_.size() +
                        radii_.size() + next_radii_.size() +
                        starts_.size() + cursor_.size() +
                        cache_.size() +
                        connection_counts_.size() + stored_counts_.size() + merge_counts_.size() +
                        merge_sum_.size();
  params_.write(&params, sizeof(params));
}

void VertexConnectionMerging::write_vcm_params(uint32_t mis, float r, uint32_t paths,
                                               uint32_t light_sample) {
  dev::VcmParams v = pass_params(config_, mis, r, paths, mask_, k_);
  v.light_sample = light_sample;
  v.pixel_radius = pixel_radius_ ? 1u : 0u;  // pass_params leaves it 0: prepare() decides
  v.light_vertex_capacity = capacity_;
  v.lvc = subpaths_.lvc;
  vcm_params_.write(&v, sizeof(v));
}

void VertexConnectionMerging::warm_up(const dev::RenderParams& params, Film& film) {
  prepare(params, film, std::max(config_.light_per_pixel, 1u));
  write_vcm_params(params.mis, config_.radius, 1, 0);
  const uint32_t none = 0;
  light_kernel_.args(light_arg_, params_, vcm_params_, none, none, vertices_, slopes_,
                     vertex_counts_, radii_, film.splat(), film.ray_counts(), connection_counts_,
                     stored_counts_);
  light_kernel_.launch(ctx_, 1);
  count_kernel_.args(0, vcm_params_, none, vertices_, vertex_counts_, starts_, cache_, cache_count_);
  count_kernel_.launch(ctx_, 1);
  fill_kernel_.args(0, vcm_params_, none, vertices_, vertex_counts_, cursor_, points_);
  fill_kernel_.launch(ctx_, 1);
  camera_kernel_.args(camera_arg_, params_, vcm_params_, none, none, none, vertices_, slopes_,
                      vertex_counts_, cache_, cache_count_, starts_, points_, radii_, next_radii_,
                      film.sum(), film.sum_sq(), film.splat(), merge_sum_, film.ray_counts(),
                      connection_counts_, merge_counts_);
  camera_kernel_.launch(ctx_, 1);
}

void VertexConnectionMerging::launch_tile(const dev::RenderParams& p, uint32_t sample,
                                          uint32_t first, uint32_t count, float r, Film& film) {
  const uint32_t mode = config_.mode;
  // The tile's light paths: k_ per pixel index, the first `count` the camera paths' own
  // (vcm_light's layout). Their first sample index: with a given K the pass's sample index
  // times K (so that devices rendering other sample indices draw other numbers), with auto
  // the count of the passes before (one device only).
  const uint32_t paths = count * k_;
  const uint32_t light_sample = config_.light_per_pixel ? sample * k_ : light_base_;
  write_vcm_params(p.mis, r, paths, light_sample);
  if (mode != dev::VCM_MODE_PT) {
    light_kernel_.args(light_arg_, params_, vcm_params_, first, count, vertices_, slopes_,
                       vertex_counts_, radii_, film.splat(), film.ray_counts(), connection_counts_,
                       stored_counts_);
    light_kernel_.launch(ctx_, count);
  }
  const bool merging = dev::vcm_mode_merges(mode);
  const bool caching = subpaths_.lvc && dev::vcm_mode_connects(mode);
  if (merging || caching) {
    // The light kernel first, so that grid_seconds times the grid alone (the queue is in
    // order: the count waits for it anyway).
    ctx_.finish();
    const auto t0 = Clock::now();
    if (merging) starts_.fill_zero();
    if (caching) cache_count_.fill_zero();
    count_kernel_.args(0, vcm_params_, paths, vertices_, vertex_counts_, starts_, cache_, cache_count_);
    count_kernel_.launch(ctx_, paths);
    if (merging) {
      // The counts become each bucket's first point (an exclusive sum; the total last), and
      // the fill's cursors start there: read one place on, start 0, running sums.
      const size_t buckets = size_t(mask_) + 1;
      bucket_starts_[0] = 0;
      starts_.read(bucket_starts_.data() + 1, buckets * sizeof(uint32_t));
      std::partial_sum(bucket_starts_.begin(), bucket_starts_.end(), bucket_starts_.begin());
      starts_.write(bucket_starts_.data(), (buckets + 1) * sizeof(uint32_t));
      cursor_.write(bucket_starts_.data(), buckets * sizeof(uint32_t));
      fill_kernel_.args(0, vcm_params_, paths, vertices_, vertex_counts_, cursor_, points_);
      fill_kernel_.launch(ctx_, paths);
    }
    ctx_.finish();
    stats_.grid_seconds += seconds_since(t0);
    if (merging) ++stats_.grids;
  }
  camera_kernel_.args(camera_arg_, params_, vcm_params_, sample, first, count, vertices_, slopes_,
                      vertex_counts_, cache_, cache_count_, starts_, points_, radii_, next_radii_,
                      film.sum(), film.sum_sq(), film.splat(), merge_sum_, film.ray_counts(),
                      connection_counts_, merge_counts_);
  camera_kernel_.launch(ctx_, count);
}

uint32_t VertexConnectionMerging::pass_k(const Film& film) {
  if (config_.light_per_pixel) return config_.light_per_pixel;
  if (chosen_k_) return chosen_k_;
  if (!pilot_) {
    const uint64_t planned = config_.planned_passes;
    if (planned && planned < LightPathPilot::kMinPlannedPasses)
      return chosen_k_ = 1;  // too short a render for a pilot
    if (stats_.passes < LightPathPilot::kWarmUp) return 1;
    pilot_.emplace(film.width(), film.height());
  }
  return pilot_->next_k();
}

std::vector<float> VertexConnectionMerging::pilot_film(Film& film) const {
  // Row by row, only the rows the pilot reads (every s-th of a large film).
  const size_t width = film.width(), n = pilot_->sampled_pixels();
  std::vector<float> rgb(3 * n), sum(4 * width), splat(4 * width);
  size_t row = SIZE_MAX;
  for (size_t i = 0; i < n; ++i) {
    const size_t p = pilot_->pixel(i), y = p / width;
    if (y != row) {
      film.sum().read(sum.data(), sum.size() * sizeof(float), y * width * 4 * sizeof(float));
      film.splat().read(splat.data(), splat.size() * sizeof(float), y * width * 4 * sizeof(float));
      row = y;
    }
    const size_t x = p % width;
    for (size_t c = 0; c < 3; ++c) rgb[3 * i + c] = sum[4 * x + c] + splat[4 * x + c];
  }
  return rgb;
}

void VertexConnectionMerging::render_sample(const dev::RenderParams& params, uint32_t sample,
                                            Film& film) {
  const size_t pixels = film.pixels();
  const float r = radius(config_.radius, config_.alpha, sample);
  if (stats_.passes == 0) stats_.first_radius = r;
  stats_.last_radius = r;
  ++stats_.passes;
  for (size_t offset = 0; offset < pixels; offset += tile_) {
    const auto count = static_cast<uint32_t>(std::min(tile_, pixels - offset));
    launch_tile(params, sample, static_cast<uint32_t>(offset), count, r, film);
  }
  if (pixel_radius_) std::swap(radii_, next_radii_);
  stats_.tiles = static_cast<uint32_t>((pixels + tile_ - 1) / tile_);
  light_base_ += k_;
}

void VertexConnectionMerging::render_pass(const dev::RenderParams& params, Film& film) {
  for (uint32_t i = 0; i < params.samples_per_pass; ++i) {
    const uint32_t sample = params.sample_offset + i;
    prepare(params, film, pass_k(film));
    if (!pilot_ || chosen_k_) {
      render_sample(params, sample, film);
      continue;
    }
    // A pilot pass: its image is the film after it less the film before, its cost the time
    // from an idle queue to its end.
    if (pilot_before_.empty()) pilot_before_ = pilot_film(film);
    ctx_.finish();
    const auto t0 = Clock::now();
    render_sample(params, sample, film);
    ctx_.finish();
    const double seconds = seconds_since(t0);
    std::vector<float> after = pilot_film(film);
    std::vector<float> pass(after.size());
    for (size_t j = 0; j < pass.size(); ++j) pass[j] = after[j] - pilot_before_[j];
    pilot_before_ = std::move(after);
    pilot_->add_pass(pass, seconds);
    if (pilot_->done()) {
      chosen_k_ = pilot_->chosen();
      pilot_before_ = {};
      stats_.pilot.assign(pilot_->candidates().begin(), pilot_->candidates().end());
      std::string figures;
      for (const LightPathPilot::Candidate& c : pilot_->candidates())
        figures += (figures.empty() ? "" : ", ") + std::string("K = ") + std::to_string(c.k) + ": " +
                   std::to_string(c.cost);
      log::verbose("vcm: --vcm-light-paths auto takes " + std::to_string(chosen_k_) +
                   " light subpaths per pixel (relMSE x seconds per pass of the pilot's passes: " +
                   figures + ")");
    }
  }
}

uint64_t VertexConnectionMerging::connections() const {
  if (!pixels_) return 0;
  uint64_t n = 0;
  for (uint32_t c : connection_counts_.read_vector<uint32_t>(pixels_)) n += c;
  return n;
}

VcmStats VertexConnectionMerging::vcm_stats() const {
  VcmStats s = stats_;
  s.alpha = config_.alpha;
  s.pixel_radii = pixel_radius_ ? 1u : 0u;
  s.merge_first = config_.merge_first ? 1u : 0u;
  s.light_per_pixel = k_;
  s.light_paths_auto = config_.light_per_pixel == 0 ? 1u : 0u;
  if (!pixels_) return s;
  for (uint32_t c : stored_counts_.read_vector<uint32_t>(pixels_)) s.light_vertices += c;
  for (uint32_t c : merge_counts_.read_vector<uint32_t>(pixels_)) s.merges += c;
  if (pixel_radius_ && s.passes) {
    const std::vector<float> rn = radii_.read_vector<float>(2 * pixels_);
    s.pixel_radius_min = s.pixel_radius_max = rn[0];
    for (size_t i = 0; i < pixels_; ++i) {
      s.pixel_radius_min = std::min(s.pixel_radius_min, rn[2 * i]);
      s.pixel_radius_max = std::max(s.pixel_radius_max, rn[2 * i]);
      s.pixel_radius_sum += rn[2 * i];
    }
    s.pixel_radius_count = pixels_;
  }
  s.connections = connections();
  return s;
}

std::vector<NamedChannel> VertexConnectionMerging::layers(uint64_t spp) const {
  if (!pixels_ || spp == 0 || !width_) return {};
  const std::vector<float> sum = merge_sum_.read_vector<float>(pixels_ * 4);
  Image merged(width_, static_cast<uint32_t>(pixels_ / width_));
  for (size_t i = 0; i < pixels_; ++i)
    for (int c = 0; c < 3; ++c) merged.rgb[3 * i + c] = float(double(sum[4 * i + c]) / double(spp));
  return {{"merged", merged}};
}

}  // namespace clpt
