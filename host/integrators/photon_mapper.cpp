#include "integrators/photon_mapper.h"

#include <algorithm>
#include <cstring>

#include "photon/kdtree.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace clpt {

PhotonMapper::PhotonMapper(const cl::Context& ctx, const SceneBuffers& scene, uint64_t global_paths,
                           uint64_t caustic_paths)
    : ctx_(ctx),
      global_paths_(global_paths ? global_paths : kDefaultGlobalPaths),
      caustic_paths_(caustic_paths),
      tracer_(ctx, scene),
      program_(ctx, "integrators/pm.cl"),
      kernel_(program_, "pm_render"),
      params_(ctx, sizeof(dev::RenderParams), CL_MEM_READ_ONLY, nullptr, "render parameters") {
  first_arg_ = scene.bind(kernel_, 0);
  // Empty maps until the first pass builds them (the warm-up launch reads none).
  global_ = empty_map();
  caustic_ = empty_map();
}

PhotonMapper::Map PhotonMapper::empty_map() const {
  return Map{cl::Buffer(ctx_, sizeof(dev::KdNode)), cl::Buffer(ctx_, sizeof(dev::Photon)), 0};
}

PhotonMapper::Map PhotonMapper::build_map(const dev::RenderParams& params, uint64_t paths,
                                          uint32_t store) {
  if (paths == 0) return empty_map();
  dev::RenderParams p = params;
  p.seed = photon_seed(params.seed) + store;  // the two maps' paths differ too
  p.sampler = dev::SAMPLER_INDEPENDENT;
  p.sample_offset = 0;
  auto t0 = Clock::now();
  // A first guess of the photons per path; emitting again with room for all of them gives
  // the same photons (same seed), so nothing is lost but time.
  size_t capacity = static_cast<size_t>(paths) * (store & PHOTON_STORE_CAUSTIC_ONLY ? 1 : 3);
  PhotonSet set = tracer_.trace(p, paths, store, capacity);
  if (set.dropped) set = tracer_.trace(p, paths, store, set.photons.size() + set.dropped);
  stats_.emit_seconds += seconds_since(t0);
  // The kernel appends photons in whatever order its work-items reach the counter; sorting
  // them by their bytes makes the map, its tree and so every estimate the same from run to
  // run (a resumed render equals an uninterrupted one).
  std::sort(set.photons.begin(), set.photons.end(), [](const dev::Photon& a, const dev::Photon& b) {
    return std::memcmp(&a, &b, sizeof(dev::Photon)) < 0;
  });
  if (set.photons.size() >= kKdMaxPoints)
    throw Error(ExitCode::Usage, "pm: " + std::to_string(set.photons.size()) +
                                     " photons, more than a kd-tree indexes; lower --photons");
  t0 = Clock::now();
  std::vector<glm::vec3> points(set.photons.size());
  for (size_t i = 0; i < points.size(); ++i)
    points[i] = glm::vec3(set.photons[i].p[0], set.photons[i].p[1], set.photons[i].p[2]);
  const KdTree tree = build_kdtree(points);
  stats_.build_seconds += seconds_since(t0);
  ++stats_.builds;
  stats_.paths += paths;
  stats_.stored += set.photons.size();
  Map map;
  map.count = static_cast<uint32_t>(set.photons.size());
  map.nodes = cl::Buffer::from_vector(ctx_, tree.nodes, CL_MEM_READ_ONLY, "photon kd-tree");
  map.photons = cl::Buffer::from_vector(ctx_, set.photons, CL_MEM_READ_ONLY, "photon map");
  stats_.device_bytes += map.nodes.size() + map.photons.size();
  return map;
}

void PhotonMapper::warm_up(const dev::RenderParams& params, Film& film) {
  tracer_.warm_up(global_paths_);
  tracer_.warm_up(caustic_paths_);
  launch(without_samples(params), film);  // reads no map
}

void PhotonMapper::render_pass(const dev::RenderParams& params, Film& film) {
  if (!built_) {
    global_ = build_map(params, global_paths_, 0u);
    caustic_ = build_map(params, caustic_paths_, PHOTON_STORE_CAUSTIC_ONLY);
    stats_.rays = tracer_.rays();
    built_ = true;
    log::verbose("pm: global map " + std::to_string(global_.count) + " photons, caustic map " +
                 std::to_string(caustic_.count) + " photons");
  }
  launch(params, film);
}

void PhotonMapper::launch(const dev::RenderParams& params, Film& film) {
  params_.write(&params, sizeof(params));
  kernel_.args(first_arg_, params_, global_.nodes, global_.photons, global_.count, caustic_.nodes,
               caustic_.photons, caustic_.count, film.sum(), film.sum_sq(), film.ray_counts());
  kernel_.launch(ctx_, film.pixels());
}

}  // namespace clpt
