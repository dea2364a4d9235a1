#include "integrators/ic_records.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "cl/programs.h"
#include "util/error.h"
#include "util/timer.h"

namespace clpt {
namespace {

static_assert(sizeof(dev::IcRecord) == 136, "IcRecord should stay 136 bytes");

// Hemisphere rays of one record-ray launch: 2^21 results of 16 bytes (32 MiB).
constexpr size_t kRaysPerLaunch = size_t(1) << 21;
// Grid points of one placement launch: 2^18 candidates of 120 bytes (30 MiB) at most.
constexpr uint32_t kPlaceChunk = uint32_t(1) << 18;

// Records whose rays one record-ray launch traces (compute_records; warm_up's largest launch).
size_t records_per_launch(size_t rays_per_record) {
  return std::max<size_t>(1, kRaysPerLaunch / rays_per_record);
}

// The cache's own sampler key: its rays must not repeat the image's.
uint32_t cache_seed(uint32_t seed) { return seed * 0x9e3779b9u + 0x1c0ffee5u; }

glm::vec3 vec(const float* v) { return glm::vec3(v[0], v[1], v[2]); }

}  // namespace

void IcRecords::strata(uint32_t rays, uint32_t* m, uint32_t* n) {
  *m = std::max<uint32_t>(1, uint32_t(std::lround(std::sqrt(double(rays) / M_PI))));
  *n = std::max<uint32_t>(1, uint32_t(std::lround(double(rays) / double(*m))));
}

IcRecords::IcRecords(const cl::Context& ctx, const SceneBuffers& scene, const IcConfig& config,
                     dev::IcGather gather, const dev::PhotonLookup& photons)
    : ctx_(ctx),
      config_(config),
      program_(ctx, programs::kIc),
      place_kernel_(program_, "ic_place"),
      rays_kernel_(program_, "ic_record_rays"),
      finish_kernel_(program_, "ic_record_finish"),
      place_params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr,
                    "irradiance cache parameters"),
      ic_params_(ctx, sizeof(dev::IcParams), CL_MEM_READ_ONLY, nullptr,
                 "irradiance cache parameters"),
      no_map_(empty_photon_map(ctx)) {
  place_arg_ = scene.bind(place_kernel_, 0);
  rays_arg_ = scene.bind(rays_kernel_, 0);
  ic_.error = config.error;
  ic_.min_spacing = config.min_spacing;
  ic_.max_spacing = config.max_spacing;
  strata(config.rays, &ic_.rays_theta, &ic_.rays_phi);
  ic_.gradients = config.gradients ? 1u : 0u;
  ic_.show_records = config.show_records ? 1u : 0u;
  ic_.gather = gather;
  ic_.photons = photons;
  stats_.rays_per_record = ic_.rays_theta * ic_.rays_phi;
  upload_records();  // empty: the warm-up reads no record
  upload_grid();
}

cl_uint IcRecords::bind_cache(cl::Kernel& kernel, cl_uint first) {
  return kernel.args(first, ic_params_, records_buf_, starts_, entries_);
}

void IcRecords::upload_records() {
  records_buf_ = records_.empty()
                     ? cl::Buffer(ctx_, sizeof(dev::IcRecord))
                     : cl::Buffer::from_vector(ctx_, records_, CL_MEM_READ_WRITE, "irradiance records");
}

void IcRecords::upload_grid() {
  grid_ = build_ic_grid(records_, ic_.error);
  starts_ = cl::Buffer::from_vector(ctx_, grid_.starts, CL_MEM_READ_ONLY, "irradiance cache grid");
  entries_ = grid_.entries.empty()
                 ? cl::Buffer(ctx_, sizeof(uint32_t))
                 : cl::Buffer::from_vector(ctx_, grid_.entries, CL_MEM_READ_ONLY,
                                           "irradiance cache grid entries");
  ic_.record_count = uint32_t(records_.size());
  ic_.level_mask = grid_.level_mask;
  ic_.bucket_mask = grid_.bucket_mask;
  ic_.inv_cell = grid_.inv_cell;
}

cl_uint IcRecords::bind_map(cl::Kernel& kernel, cl_uint first) {
  return kernel.args(first, map_->nodes, map_->photons, map_->count);
}

void IcRecords::warm_up(const dev::RenderParams& params, size_t pixels) {
  // Every kernel over nothing (grid 0 x 0, batch 0), at the smallest and the largest of the
  // sizes the build launches it with: PoCL compiles a work-group function per grid size class
  // ("smallgrid" or not) at its first launch, and two devices of one PoCL platform that
  // compile the same one at once, each on its own thread, corrupt PoCL 3.1's cache of them
  // (pocl_release_dlhandle_cache's assertion `found->ref_count > 0` aborts the process: seen
  // with ic on two "basic" devices, where the first pass's record rays came in the large class
  // on both at once). Warmed up here, while the renderer sets its devices up one after another,
  // each class is compiled once, before any pass.
  pixels_ = pixels;
  lookup_counts_ = cl::Buffer(ctx_, pixels_ * 3 * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr,
                              "irradiance cache lookup counts");
  lookup_counts_.fill_zero();
  marks_ = cl::Buffer(ctx_, pixels_ * sizeof(uint32_t), CL_MEM_READ_ONLY, nullptr,
                      "irradiance record marks");
  marks_.fill_zero();
  const dev::RenderParams none = without_samples(params);
  place_params_.write(&none, sizeof(none));
  dev::IcParams idle = ic_;
  idle.grid_w = idle.grid_h = 0;
  idle.batch = 0;
  ic_params_.write(&idle, sizeof(idle));
  cl::Buffer candidates(ctx_, sizeof(dev::IcRecord)), count(ctx_, sizeof(uint32_t));
  results_ = cl::Buffer(ctx_, sizeof(float) * 4);
  place_kernel_.args(bind_cache(place_kernel_, place_kernel_.args(place_arg_, place_params_)),
                     candidates, count);
  for (size_t n : {size_t(1), std::min<size_t>(pixels_, kPlaceChunk)}) place_kernel_.launch(ctx_, n);
  bind_map(rays_kernel_,
           rays_kernel_.args(rays_arg_, place_params_, ic_params_, records_buf_, results_));
  const size_t per = size_t(ic_.rays_theta) * ic_.rays_phi;
  const size_t batch = records_per_launch(per);
  for (size_t n : {per, batch * per}) rays_kernel_.launch(ctx_, n);
  finish_kernel_.args(0, ic_params_, records_buf_, results_);
  for (size_t n : {size_t(1), batch}) finish_kernel_.launch(ctx_, n);
}

cl_uint IcRecords::bind_image(cl::Kernel& kernel, cl_uint first) {
  return kernel.args(bind_cache(kernel, first), marks_, lookup_counts_);
}

void IcRecords::write_params() { ic_params_.write(&ic_, sizeof(ic_)); }

void IcRecords::build(const dev::RenderParams& params, const DevicePhotonMap& global,
                      Clock::time_point started, const std::atomic<bool>* stop) {
  const auto t0 = Clock::now();
  if (ic_.gather != dev::IC_GATHER_PATHS) map_ = &global;
  width_ = params.width;
  height_ = params.height;
  dev::RenderParams pp = params;
  pp.sampler = dev::SAMPLER_INDEPENDENT;
  pp.seed = cache_seed(params.seed);
  pp.sample_offset = 0;
  pp.samples_per_pass = 1;
  place_params_.write(&pp, sizeof(pp));
  // A pixel's footprint along a camera path: the film's height over the pixels, at
  // distance 1 (perspective) or everywhere (orthographic).
  const float up = glm::length(vec(params.camera.up));
  const float pixel = 2.0f * up / float(std::max<uint32_t>(params.height, 1));
  const bool ortho = params.camera.type == dev::CAMERA_ORTHOGRAPHIC;
  ic_.footprint_per_distance = ortho ? 0.0f : pixel;
  ic_.footprint_constant = ortho ? pixel : 1e-7f;
  uint32_t step = 1;
  while (step * 2 <= std::max<uint32_t>(1, std::max(width_, height_) / 8)) step *= 2;
  for (; step >= 1; step /= 2) {
    place(step);
    ++stats_.placement_passes;
  }
  // One more pass at every pixel through a random point in it: the image's samples are
  // jittered, and a centre's record need not cover the whole pixel (curved surfaces).
  ic_.jitter = 1;
  place(1);
  ic_.jitter = 0;
  ++stats_.placement_passes;
  // Under --time, every record takes another batch of rays while its share of the time
  // lasts: the records' noise, which no number of image samples averages away, falls.
  // Ctrl-C ends the refinement (the renderer then saves after this first pass).
  if (config_.refine_seconds > 0.0 && !records_.empty()) {
    while (seconds_since(started) < config_.refine_seconds && !(stop && stop->load())) {
      compute_records(0, records_.size());
      ++stats_.refinements;
    }
    records_buf_.read(records_.data(), records_.size() * sizeof(dev::IcRecord));
    upload_grid();
  }
  std::vector<uint32_t> marks(pixels_, 0u);
  for (const dev::IcRecord& r : records_)
    if (r.pixel < marks.size()) marks[r.pixel] = 1u;
  marks_.write(marks.data(), marks.size() * sizeof(uint32_t));
  built_ = true;
  stats_.records = records_.size();
  stats_.build_seconds += seconds_since(t0);
  stats_.device_bytes = records_buf_.size() + starts_.size() + entries_.size() + results_.size() +
                        marks_.size() + lookup_counts_.size();
  write_params();
}

void IcRecords::place(uint32_t step) {
  ic_.step = step;
  ic_.grid_w = (width_ + step - 1) / step;
  ic_.grid_h = (height_ + step - 1) / step;
  // Grid points in launches of at most kPlaceChunk, so the candidate buffer stays small
  // (each point can make one candidate) whatever the image size.
  const uint32_t points = ic_.grid_w * ic_.grid_h;
  ic_.capacity = std::min(points, kPlaceChunk);
  cl::Buffer candidates(ctx_, size_t(ic_.capacity) * sizeof(dev::IcRecord), CL_MEM_READ_WRITE,
                        nullptr, "irradiance cache candidates");
  cl::Buffer count(ctx_, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "candidate count");
  std::vector<dev::IcRecord> cand;
  for (uint32_t first = 0; first < points; first += ic_.capacity) {
    ic_.grid_first = first;
    ic_params_.write(&ic_, sizeof(ic_));
    count.fill_zero();
    place_kernel_.args(bind_cache(place_kernel_, place_kernel_.args(place_arg_, place_params_)),
                       candidates, count);
    place_kernel_.launch(ctx_, std::min(ic_.capacity, points - first));
    const uint32_t found = std::min(count.read_vector<uint32_t>(1)[0], ic_.capacity);
    const std::vector<dev::IcRecord> chunk = candidates.read_vector<dev::IcRecord>(found);
    cand.insert(cand.end(), chunk.begin(), chunk.end());
  }
  const size_t found = cand.size();
  stats_.candidates += found;
  // Work-items append in no fixed order: sorted by pixel, the cache is the same every run.
  std::sort(cand.begin(), cand.end(), [](const dev::IcRecord& a, const dev::IcRecord& b) {
    return a.pixel < b.pixel;
  });
  // Thinning: a candidate within the smallest validity radius (min spacing footprints) of
  // one already kept, at the same depth and with a normal within the error, would be
  // covered by that one's record; keep the first.
  float cell = 0.0f;
  for (const dev::IcRecord& c : cand) cell = std::max(cell, ic_.min_spacing * c.r);
  const size_t first = records_.size();
  if (cell > 0.0f) {
    const float inv = 1.0f / cell;
    std::unordered_map<uint64_t, std::vector<uint32_t>> kept;
    auto key = [](int64_t x, int64_t y, int64_t z) {
      return (uint64_t(x) * 73856093u) ^ (uint64_t(y) * 19349663u) ^ (uint64_t(z) * 83492791u);
    };
    const float cos_max = 1.0f - ic_.error * ic_.error;
    for (const dev::IcRecord& c : cand) {
      const glm::vec3 p = vec(c.p), n = vec(c.n);
      const int64_t cx = int64_t(std::floor(p.x * inv)), cy = int64_t(std::floor(p.y * inv)),
                    cz = int64_t(std::floor(p.z * inv));
      bool covered = false;
      for (int64_t dz = -1; dz <= 1 && !covered; ++dz)
        for (int64_t dy = -1; dy <= 1 && !covered; ++dy)
          for (int64_t dx = -1; dx <= 1 && !covered; ++dx) {
            auto it = kept.find(key(cx + dx, cy + dy, cz + dz));
            if (it == kept.end()) continue;
            for (uint32_t i : it->second) {
              const dev::IcRecord& k = records_[i];
              const float reach = ic_.min_spacing * std::min(c.r, k.r);
              if (k.depth == c.depth && glm::dot(n, vec(k.n)) > cos_max &&
                  glm::length(p - vec(k.p)) < reach) {
                covered = true;
                break;
              }
            }
          }
      if (covered) continue;
      kept[key(cx, cy, cz)].push_back(uint32_t(records_.size()));
      records_.push_back(c);
    }
  }
  const size_t added = records_.size() - first;
  if (added == 0) return;
  // The candidates go up with the records (their r is the footprint, which the record
  // kernels replace with R); the finished records come back for the grid, which the host
  // builds; the device's copy of the records is already the final one.
  upload_records();
  compute_records(first, added);
  records_buf_.read(records_.data() + first, added * sizeof(dev::IcRecord),
                    first * sizeof(dev::IcRecord));
  upload_grid();
}

void IcRecords::compute_records(size_t first, size_t count) {
  const auto t0 = Clock::now();
  const size_t per = size_t(ic_.rays_theta) * ic_.rays_phi;
  const size_t batch = records_per_launch(per);
  const size_t results_bytes = std::min(batch, count) * per * sizeof(float) * 4;
  if (results_.size() < results_bytes)
    results_ = cl::Buffer(ctx_, results_bytes, CL_MEM_READ_WRITE, nullptr,
                          "irradiance record rays");
  for (size_t done = 0; done < count; done += batch) {
    ic_.first = uint32_t(first + done);
    ic_.batch = uint32_t(std::min(batch, count - done));
    ic_params_.write(&ic_, sizeof(ic_));
    bind_map(rays_kernel_,
             rays_kernel_.args(rays_arg_, place_params_, ic_params_, records_buf_, results_));
    rays_kernel_.launch(ctx_, size_t(ic_.batch) * per);
    finish_kernel_.args(0, ic_params_, records_buf_, results_);
    finish_kernel_.launch(ctx_, ic_.batch);
  }
  ctx_.finish();
  stats_.record_seconds += seconds_since(t0);
}

IcStats IcRecords::stats() const {
  IcStats s = stats_;
  if (pixels_) {
    const std::vector<uint32_t> counts = lookup_counts_.read_vector<uint32_t>(pixels_ * 3);
    for (size_t i = 0; i < pixels_; ++i) {
      s.lookups += counts[3 * i];
      s.records_used += counts[3 * i + 1];
      s.misses += counts[3 * i + 2];
    }
  }
  return s;
}

IcNoCache::IcNoCache(const cl::Context& ctx)
    : records_(ctx, sizeof(dev::IcRecord)),
      starts_(ctx, sizeof(uint32_t)),
      entries_(ctx, sizeof(uint32_t)),
      marks_(ctx, sizeof(uint32_t)),
      counts_(ctx, 3 * sizeof(uint32_t)) {
  const dev::IcParams none{};  // record_count 0, show_records 0
  params_ = cl::Buffer(ctx, sizeof(none), CL_MEM_READ_ONLY, &none, "irradiance cache parameters");
}

cl_uint IcNoCache::bind_image(cl::Kernel& kernel, cl_uint first) {
  return kernel.args(first, params_, records_, starts_, entries_, marks_, counts_);
}

}  // namespace clpt
