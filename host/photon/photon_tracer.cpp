#include "photon/photon_tracer.h"

#include <algorithm>

#include "util/error.h"

namespace clpt {

static_assert(sizeof(dev::Photon) == 64, "Photon should stay 64 bytes");

PhotonTracer::PhotonTracer(const cl::Context& ctx, const SceneBuffers& scene)
    : ctx_(ctx),
      program_(ctx, "integrators/photon.cl"),
      kernel_(program_, "photon_emit"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  first_arg_ = scene.bind(kernel_, 0);
}

PhotonSet PhotonTracer::trace(const dev::RenderParams& params, uint64_t paths, bool caustic_only,
                              size_t capacity) {
  if (paths > 0xffffffffull)
    throw Error(ExitCode::Usage, "at most 2^32 - 1 photon paths per pass");
  PhotonSet set;
  set.paths = paths;
  if (paths == 0 || capacity == 0) return set;
  params_.write(&params, sizeof(params));
  cl::Buffer photons(ctx_, capacity * sizeof(dev::Photon), CL_MEM_READ_WRITE, nullptr, "photon map");
  cl::Buffer count(ctx_, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "photon count");
  cl::Buffer rays(ctx_, sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "photon ray count");
  count.fill_zero();
  rays.fill_zero();
  const float inv_paths = float(1.0 / double(paths));
  const uint32_t cap = static_cast<uint32_t>(std::min<size_t>(capacity, 0xffffffffu));
  const uint32_t caustic = caustic_only ? 1u : 0u;
  constexpr uint64_t kChunk = uint64_t(1) << 20;  // paths per launch
  for (uint64_t first = 0; first < paths; first += kChunk) {
    const auto n = static_cast<uint32_t>(std::min(kChunk, paths - first));
    kernel_.args(first_arg_, params_, static_cast<uint32_t>(first), n, inv_paths, caustic, photons,
                 count, cap, rays);
    kernel_.launch(ctx_, n);
  }
  const uint32_t stored = count.read_vector<uint32_t>(1)[0];
  set.rays = rays.read_vector<uint32_t>(1)[0];
  const size_t kept = std::min<size_t>(stored, cap);
  set.dropped = stored - kept;
  set.photons.resize(kept);
  if (kept) photons.read(set.photons.data(), kept * sizeof(dev::Photon));
  return set;
}

}  // namespace clpt
