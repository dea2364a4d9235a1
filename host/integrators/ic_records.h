// Ward's irradiance cache on the device (kernels/integrators/ic.cl,
// docs/concepts/irradiance-caching.md): the records, how they are placed and computed, and
// the lookup grid over them, for the integrators that read the cache in their image kernels
// (ic; pm --final-gather-cache). build() runs placement passes over a coarse-to-fine pixel
// grid (step 2^k ... 1) that find the camera's first non-delta vertices no record covers yet;
// the host thins each pass's candidates (none within another's smallest validity radius),
// the device computes their records (one work-item per hemisphere ray, then one per record),
// and the host rebuilds the lookup grid (ic_grid.h) from the records read back.
//
// A record's hemisphere rays estimate the light where they land by path tracing, or, given
// a global photon map, by its density estimate there (Jensen 2001, ch. 9: the cache as photon
// mapping's final gather).
#pragma once

#include <atomic>
#include <vector>

#include "integrators/ic_grid.h"
#include "integrators/integrator.h"
#include "integrators/photon_map.h"
#include "shared/ic_types.h"
#include "util/timer.h"

namespace clpt {

class IcRecords {
 public:
  // gather (shared/ic_types.h): what a record's hemisphere ray adds where it lands: path
  // tracing (ic), the global map's estimate and the emission seen through delta and glossy
  // surfaces beyond the first hit (ic --ic-photons), or the map's estimate alone, a caustic
  // map holding L S+ D light at the lookup (pm --final-gather-cache).
  // photons: how records read the map (pm's --knn, --pm-max-radius, --pm-filter; unused with
  // IC_GATHER_PATHS).
  IcRecords(const cl::Context& ctx, const SceneBuffers& scene, const IcConfig& config,
            dev::IcGather gather, const dev::PhotonLookup& photons = {});

  // The program of the record kernels (ic.cl), whose ic_render an integrator may use.
  const cl::Program& program() const { return program_; }
  // Every record kernel once over nothing, and the per-pixel buffers for `pixels` pixels.
  void warm_up(const dev::RenderParams& params, size_t pixels);
  // Places and computes the records for the image params describes (once); photon
  // gathering reads `global` (ignored with IC_GATHER_PATHS), which must outlive this. Under --time the records refine
  // until config.refine_seconds have passed since `started` or *stop (Ctrl-C) is set.
  void build(const dev::RenderParams& params, const DevicePhotonMap& global,
             Clock::time_point started, const std::atomic<bool>* stop);
  bool built() const { return built_; }
  // Uploads the lookup parameters a render launch reads.
  void write_params();
  // Binds, from `first`, what an image kernel's IC_IMAGE_ARGS take: the cache's parameters,
  // records, grid, the show-records marks and the per-pixel lookup counts. Returns the next
  // free index.
  cl_uint bind_image(cl::Kernel& kernel, cl_uint first);

  const std::vector<dev::IcRecord>& records() const { return records_; }
  IcStats stats() const;  // with the lookups the image kernels counted
  // M and N of M x N hemisphere rays for `rays` asked for: N ~ pi M (Ward's square-ish
  // strata), at least 1 x 1.
  static void strata(uint32_t rays, uint32_t* m, uint32_t* n);

 private:
  void place(uint32_t step);
  void compute_records(size_t first, size_t count);
  void upload_records();  // records_ to the device
  void upload_grid();     // the grid over records_ to the device
  cl_uint bind_cache(cl::Kernel& kernel, cl_uint first);
  cl_uint bind_map(cl::Kernel& kernel, cl_uint first);

  const cl::Context& ctx_;
  IcConfig config_;
  cl::Program program_;
  cl::Kernel place_kernel_, rays_kernel_, finish_kernel_;
  cl::Buffer place_params_, ic_params_;
  cl::Buffer records_buf_, starts_, entries_, marks_, lookup_counts_;
  cl::Buffer results_;
  DevicePhotonMap no_map_;
  const DevicePhotonMap* map_ = &no_map_;  // the integrator's global map once built
  dev::IcParams ic_{};
  std::vector<dev::IcRecord> records_;
  IcGrid grid_;
  bool built_ = false;
  size_t pixels_ = 0;
  uint32_t width_ = 0, height_ = 0;
  cl_uint place_arg_ = 0, rays_arg_ = 0;
  IcStats stats_;
};

// What IC_IMAGE_ARGS bind for an image kernel that reads no cache (pm without
// --final-gather-cache): parameters with no records, so every lookup misses and none is
// counted, and one-element buffers for the rest.
class IcNoCache {
 public:
  explicit IcNoCache(const cl::Context& ctx);
  // As IcRecords::bind_image; returns the next free index.
  cl_uint bind_image(cl::Kernel& kernel, cl_uint first);

 private:
  cl::Buffer params_, records_, starts_, entries_, marks_, counts_;
};

}  // namespace clpt
