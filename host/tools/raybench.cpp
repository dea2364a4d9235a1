// clpt-raybench: clpt's BVH traversal alone, on the ray sets of Embree's benchmark
// (../shared/tools/embree/embree_bench.cpp), for a like-for-like figure against Embree
// (issue 21; docs/BENCHMARKS.md):
//   primary  one pinhole ray per pixel centre of a RES x RES image from the scene's camera
//            (tan(yfov / 2) on both axes), closest hit;
//   random   N incoherent rays, each from a uniform point on a triangle chosen by area, in a
//            cosine-distributed direction about its geometric normal (counter-clockwise front),
//            the origin moved 1e-5 of the scene's diagonal along the normal: closest hit and
//            any hit (t_far infinite). The same generator (std::mt19937_64, seed 12345) and
//            draws as Embree's benchmark.
// Each set is traced again and again for --seconds; the figure is rays per second of kernel
// time (launch to finish), with each set's hit rate.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "cl/buffer.h"
#include "cl/context.h"
#include "cl/device.h"
#include "cl/program.h"
#include "cl/programs.h"
#include "render/camera_setup.h"
#include "render/scene_buffers.h"
#include "scene/gltf_loader.h"
#include "util/error.h"

namespace clpt {
namespace {

struct RaySet {
  std::vector<cl_float4> origins, directions;
};

void push(RaySet& set, glm::vec3 o, glm::vec3 d) {
  set.origins.push_back({{o.x, o.y, o.z, 0.0f}});
  set.directions.push_back({{d.x, d.y, d.z, 0.0f}});
}

// Through the renderer's own camera set-up (right and up already scaled by tan(yfov / 2) on a
// square film); a pinhole, as Embree's benchmark.
RaySet primary_rays(const Camera& camera, int res) {
  const dev::CameraData c = camera_data(camera, uint32_t(res), uint32_t(res));
  const glm::vec3 eye(c.origin[0], c.origin[1], c.origin[2]);
  const glm::vec3 fw(c.forward[0], c.forward[1], c.forward[2]);
  const glm::vec3 rt(c.right[0], c.right[1], c.right[2]), up(c.up[0], c.up[1], c.up[2]);
  RaySet set;
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x) {
      const float px = (float(x) + 0.5f) / float(res) * 2.0f - 1.0f;
      const float py = 1.0f - (float(y) + 0.5f) / float(res) * 2.0f;
      push(set, eye, glm::normalize(fw + rt * px + up * py));
    }
  return set;
}

RaySet random_rays(const Scene& scene, size_t n) {
  const std::vector<glm::vec3>& pos = scene.positions;
  const glm::vec3 ext = scene.bounds().extent();
  const float eps = 1e-5f * glm::length(ext);
  std::vector<double> cdf(scene.triangles.size());
  double acc = 0.0;
  for (size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::uvec3 tri = scene.triangles[t];
    acc += 0.5 * double(glm::length(glm::cross(pos[tri.y] - pos[tri.x], pos[tri.z] - pos[tri.x])));
    cdf[t] = acc;
  }
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  RaySet set;
  for (size_t i = 0; i < n; ++i) {
    const double r = double(u(rng)) * acc;
    size_t t = size_t(std::lower_bound(cdf.begin(), cdf.end(), r) - cdf.begin());
    t = std::min(t, cdf.size() - 1);
    const glm::uvec3 tri = scene.triangles[t];
    const glm::vec3 a = pos[tri.x], b = pos[tri.y], c = pos[tri.z];
    const float u1 = u(rng), u2 = u(rng), su = std::sqrt(u1);
    const glm::vec3 p = a * (1.0f - su) + b * (su * (1.0f - u2)) + c * (su * u2);
    const glm::vec3 nrm = glm::normalize(glm::cross(b - a, c - a));
    const float r1 = u(rng), r2 = u(rng);
    const float rr = std::sqrt(r1), phi = 6.2831853f * r2;
    const glm::vec3 tx = std::fabs(nrm.x) > 0.5f ? glm::normalize(glm::cross(glm::vec3(0, 1, 0), nrm))
                                                 : glm::normalize(glm::cross(glm::vec3(1, 0, 0), nrm));
    const glm::vec3 ty = glm::cross(nrm, tx);
    const glm::vec3 d = glm::normalize(tx * (rr * std::cos(phi)) + ty * (rr * std::sin(phi)) +
                                       nrm * std::sqrt(std::max(0.0f, 1.0f - r1)));
    push(set, p + nrm * eps, d);
  }
  return set;
}

struct Figure {
  std::string name;
  size_t rays = 0;
  double seconds = 0.0, hit_rate = 0.0;
};

Figure trace(const cl::Context& ctx, const SceneBuffers& buffers, const cl::Program& program,
             const char* kernel_name, const char* label, const RaySet& set, double seconds) {
  const auto n = static_cast<uint32_t>(set.origins.size());
  cl::Buffer org = cl::Buffer::from_vector(ctx, set.origins, CL_MEM_READ_ONLY, "ray origins");
  cl::Buffer dir = cl::Buffer::from_vector(ctx, set.directions, CL_MEM_READ_ONLY, "ray directions");
  cl::Buffer hits(ctx, size_t(n) * sizeof(uint32_t), CL_MEM_READ_WRITE, nullptr, "ray hits");
  cl::Kernel kernel(program, kernel_name);
  kernel.args(buffers.bind(kernel, 0), org, dir, n, hits);
  kernel.launch(ctx, n);  // warm-up: PoCL compiles for the work-group size at the first launch
  ctx.finish();
  Figure f;
  f.name = label;
  const auto t0 = std::chrono::steady_clock::now();
  do {
    kernel.launch(ctx, n);
    ctx.finish();
    f.rays += n;
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (f.seconds < seconds);
  uint64_t hit = 0;
  for (uint32_t h : hits.read_vector<uint32_t>(n)) hit += h;
  f.hit_rate = n ? double(hit) / double(n) : 0.0;
  return f;
}

int run(int argc, char** argv) {
  CLI::App app{"clpt-raybench: clpt's ray traversal alone (closest and any hit) on Embree's "
               "benchmark ray sets"};
  std::string scene_file, device = "pocl", json_file;
  int res = 512;
  size_t rays = 2000000;
  double seconds = 2.0;
  app.add_option("scene", scene_file, "glTF 2.0 scene (.gltf or .glb)")->required();
  app.add_option("--device", device, "OpenCL device, as clpt's --device [pocl]");
  app.add_option("--res", res, "primary rays: RES x RES pixel centres [512]")->check(CLI::Range(1, 8192));
  app.add_option("--rays", rays, "incoherent rays [2000000]")->check(CLI::Range(size_t(1), size_t(1) << 26));
  app.add_option("--seconds", seconds, "time per ray set [2]")->check(CLI::Range(0.0, 3600.0));
  app.add_option("--json", json_file, "write the figures as JSON here");
  BvhBuildOptions bvh_options;
  int max_leaf = 0;  // 0: as clpt builds it for this device (kMaxLeafLanes on CPU devices)
  app.add_option("--max-leaf", max_leaf,
                 "BVH: triangles per leaf at most [as clpt: 8 on CPU devices, else 4]")
      ->check(CLI::Range(1, 64));
  app.add_option("--bins", bvh_options.bins, "BVH: SAH bins per axis [16]")->check(CLI::Range(2, 256));
  CLI11_PARSE(app, argc, argv);

  const Scene scene = load_gltf(scene_file);
  if (scene.triangles.empty()) throw Error(ExitCode::BadInput, scene_file + ": no triangles");
  const cl::Context ctx(cl::select_device(device));
  bvh_options.max_leaf_size = max_leaf ? max_leaf : bvh_max_leaf(ctx.device());
  const auto tb = std::chrono::steady_clock::now();
  const Bvh bvh = build_bvh(scene.positions, scene.triangles, bvh_options);
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
  const SceneBuffers buffers(ctx, flatten_scene(scene, bvh));
  const cl::Program program(ctx, programs::kRaybench);
  const RaySet primary = primary_rays(choose_camera(scene, ""), res);
  const RaySet random = random_rays(scene, rays);

  std::printf("%s: %zu triangles, BVH built in %.3f s (%zu binary nodes, depth %d; %zu 4-wide nodes, "
              "depth %d), device %s\n",
              scene_file.c_str(), scene.triangles.size(), build_s, bvh.nodes.size(), bvh.depth, bvh.wide.size(),
              bvh.wide_depth, ctx.device().label().c_str());
  std::vector<Figure> figures = {
      trace(ctx, buffers, program, "raybench_closest", "primary closest", primary, seconds),
      trace(ctx, buffers, program, "raybench_closest", "random closest", random, seconds),
      trace(ctx, buffers, program, "raybench_any", "random any", random, seconds)};
  nlohmann::json j = {{"scene", scene_file}, {"triangles", scene.triangles.size()},
                      {"max_leaf", bvh_options.max_leaf_size}, {"bins", bvh_options.bins},
                      {"bvh_build_seconds", build_s}, {"device", ctx.device().label()},
                      {"figures", nlohmann::json::array()}};
  for (const Figure& f : figures) {
    const double mrays = double(f.rays) / f.seconds / 1e6;
    std::printf("  %-16s %8.2f Mrays/s   (%zu rays in %.2f s, hit rate %.3f)\n", f.name.c_str(),
                mrays, f.rays, f.seconds, f.hit_rate);
    j["figures"].push_back({{"name", f.name}, {"mrays_per_second", mrays}, {"rays", f.rays},
                            {"seconds", f.seconds}, {"hit_rate", f.hit_rate}});
  }
  if (!json_file.empty()) std::ofstream(json_file) << j.dump(2) << "\n";
  return 0;
}

}  // namespace
}  // namespace clpt

int main(int argc, char** argv) {
  try {
    return clpt::run(argc, argv);
  } catch (const clpt::Error& e) {
    std::fprintf(stderr, "clpt-raybench: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clpt-raybench: internal error: %s\n", e.what());
    return 70;  // as clpt's
  }
}
