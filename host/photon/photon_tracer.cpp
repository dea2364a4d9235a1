#include "photon/photon_tracer.h"

#include <algorithm>

#include "cl/programs.h"
#include "util/error.h"

namespace clpt {

static_assert(sizeof(dev::Photon) == 64, "Photon should stay 64 bytes");

PhotonTracer::PhotonTracer(const cl::Context& ctx, const SceneBuffers& scene)
    : ctx_(ctx),
      program_(ctx, programs::kPhoton),
      kernel_(program_, "photon_emit"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters"),
      count_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "photon count"),
      ray_count_(ctx, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "photon ray count") {
  first_arg_ = scene.bind(kernel_, 0);
}

uint64_t PhotonTracer::emit(const dev::RenderParams& params, uint64_t paths, uint32_t store,
                            cl::Buffer& photons, size_t capacity) {
  if (paths > 0xffffffffull)
    throw Error(ExitCode::Usage, "at most 2^32 - 1 photon paths per pass");
  if (paths == 0) return 0;
  params_.write(&params, sizeof(params));
  count_.fill_zero();
  ray_count_.fill_zero();
  const float inv_paths = float(1.0 / double(paths));
  const uint32_t cap = static_cast<uint32_t>(std::min<size_t>(capacity, 0xffffffffu));
  uint64_t made = 0;
  for (uint64_t first = 0; first < paths; first += kChunk) {
    const auto n = static_cast<uint32_t>(std::min(kChunk, paths - first));
    // Each launch appends after the photons kept so far.
    const uint32_t offset = static_cast<uint32_t>(std::min<uint64_t>(made, cap));
    const uint32_t room = cap - offset;
    kernel_.args(first_arg_, params_, static_cast<uint32_t>(first), n, inv_paths, store, photons,
                 offset, count_, room, ray_count_);
    kernel_.launch(ctx_, n);
    made += count_.read_vector<uint32_t>(1)[0];
    rays_ += ray_count_.read_vector<uint32_t>(1)[0];
    count_.fill_zero();
    ray_count_.fill_zero();
  }
  return made;
}

void PhotonTracer::warm_up(uint64_t paths) {
  const uint32_t none = 0;
  cl::Buffer photons(ctx_, sizeof(dev::Photon));
  kernel_.args(first_arg_, params_, none, none, 1.0f, none, photons, none, count_, none, ray_count_);
  kernel_.launch(ctx_, static_cast<size_t>(std::clamp<uint64_t>(paths, 1, kChunk)));
}

PhotonSet PhotonTracer::trace(const dev::RenderParams& params, uint64_t paths, uint32_t store,
                              size_t capacity) {
  PhotonSet set;
  set.paths = paths;
  if (paths == 0 || capacity == 0) return set;
  cl::Buffer photons(ctx_, capacity * sizeof(dev::Photon), CL_MEM_READ_WRITE, nullptr, "photon map");
  const uint64_t rays_before = rays_;
  const uint64_t made = emit(params, paths, store, photons, capacity);
  set.rays = rays_ - rays_before;
  const size_t kept = static_cast<size_t>(std::min<uint64_t>(made, capacity));
  set.dropped = made - kept;
  set.photons.resize(kept);
  if (kept) photons.read(set.photons.data(), kept * sizeof(dev::Photon));
  return set;
}

}  // namespace clpt
