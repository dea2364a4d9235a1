#include "integrators/photon_map.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "photon/kdtree.h"
#include "util/error.h"
#include "util/timer.h"

namespace clpt {

DevicePhotonMap empty_photon_map(const cl::Context& ctx) {
  return DevicePhotonMap{cl::Buffer(ctx, sizeof(dev::KdNode)), cl::Buffer(ctx, sizeof(dev::Photon)), 0};
}

DevicePhotonMap build_photon_map(const cl::Context& ctx, PhotonTracer& tracer,
                                 const dev::RenderParams& params, uint64_t paths, uint32_t store,
                                 const char* who, PhotonStats& stats) {
  if (paths == 0) return empty_photon_map(ctx);
  dev::RenderParams p = params;
  p.seed = photon_map_seed(params.seed) + store;  // a global and a caustic map's paths differ
  p.sampler = dev::SAMPLER_INDEPENDENT;
  p.sample_offset = 0;
  auto t0 = Clock::now();
  // A first guess of the photons per path; emitting again with room for all of them gives
  // the same photons (same seed), so nothing is lost but time.
  size_t capacity = static_cast<size_t>(paths) * (store & PHOTON_STORE_CAUSTIC_ONLY ? 1 : 3);
  PhotonSet set = tracer.trace(p, paths, store, capacity);
  if (set.dropped) set = tracer.trace(p, paths, store, set.photons.size() + set.dropped);
  stats.emit_seconds += seconds_since(t0);
  // The kernel appends photons in whatever order its work-items reach the counter; sorting
  // them by their bytes makes the map, its tree and so every estimate the same from run to
  // run (a resumed render equals an uninterrupted one).
  std::sort(set.photons.begin(), set.photons.end(), [](const dev::Photon& a, const dev::Photon& b) {
    return std::memcmp(&a, &b, sizeof(dev::Photon)) < 0;
  });
  if (set.photons.size() >= kKdMaxPoints)
    throw Error(ExitCode::Usage, std::string(who) + ": " + std::to_string(set.photons.size()) +
                                     " photons, more than a kd-tree indexes; lower --photons");
  t0 = Clock::now();
  std::vector<glm::vec3> points(set.photons.size());
  for (size_t i = 0; i < points.size(); ++i)
    points[i] = glm::vec3(set.photons[i].p[0], set.photons[i].p[1], set.photons[i].p[2]);
  const KdTree tree = build_kdtree(points);
  stats.build_seconds += seconds_since(t0);
  ++stats.builds;
  stats.paths += paths;
  stats.stored += set.photons.size();
  DevicePhotonMap map;
  map.count = static_cast<uint32_t>(set.photons.size());
  map.nodes = cl::Buffer::from_vector(ctx, tree.nodes, CL_MEM_READ_ONLY, "photon kd-tree");
  map.photons = cl::Buffer::from_vector(ctx, set.photons, CL_MEM_READ_ONLY, "photon map");
  stats.device_bytes += map.nodes.size() + map.photons.size();
  return map;
}

}  // namespace clpt
