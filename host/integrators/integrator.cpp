#include "integrators/integrator.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cl/programs.h"
#include "integrators/bdpt.h"
#include "integrators/indirect1.h"
#include "integrators/irradiance_cache.h"
#include "integrators/light_tracer.h"
#include "integrators/megakernel.h"
#include "integrators/metropolis.h"
#include "integrators/photon_mapper.h"
#include "integrators/sppm.h"
#include "integrators/vcm.h"
#include "shared/ao_types.h"
#include "util/error.h"

namespace clpt {
namespace {

using Config = IntegratorConfig;

std::unique_ptr<Integrator> make_pt(const cl::Context& ctx, const SceneBuffers& s, const Config&) {
  return std::make_unique<MegakernelIntegrator>(ctx, s, "pt", programs::kPt, "pt_render");
}
// `direct` is the path tracer stopped after one bounce (the row's max_depth_cap).
std::unique_ptr<Integrator> make_direct(const cl::Context& ctx, const SceneBuffers& s, const Config&) {
  return std::make_unique<MegakernelIntegrator>(ctx, s, "direct", programs::kPt, "pt_render");
}
// `indirect1`: the light after exactly one bounce, by the generator --indirect names.
std::unique_ptr<Integrator> make_indirect1(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<OneBounceIndirect>(ctx, s, c.indirect);
}
std::unique_ptr<Integrator> make_ao(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  dev::AoParams ao{};
  ao.radius = c.ao.radius > 0.0f ? c.ao.radius : 0.1f * c.scale.diagonal;
  std::vector<unsigned char> bytes(sizeof(ao));
  std::memcpy(bytes.data(), &ao, sizeof(ao));
  return std::make_unique<MegakernelIntegrator>(ctx, s, "ao", programs::kAo, "ao_render", bytes);
}
std::unique_ptr<Integrator> make_lt(const cl::Context& ctx, const SceneBuffers& s, const Config&) {
  return std::make_unique<LightTracer>(ctx, s);
}
std::unique_ptr<Integrator> make_bdpt(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<BidirectionalPathTracer>(ctx, s, c.bdpt);
}
std::unique_ptr<Integrator> make_pm(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<PhotonMapper>(ctx, s, c.pm, c.scale,
                                        c.pm.final_gather_cache ? &c.ic : nullptr);
}
std::unique_ptr<Integrator> make_mlt(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<Metropolis>(ctx, s, c.mlt);
}
std::unique_ptr<Integrator> make_ic(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  IcConfig ic = c.ic;
  if (c.time_limit > 0.0) ic.refine_seconds = kIcRefineShare * c.time_limit;
  return std::make_unique<IrradianceCache>(ctx, s, ic, photon_lookup(c.pm, c.scale));
}
std::unique_ptr<Integrator> make_vcm(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<VertexConnectionMerging>(ctx, s, c.vcm, c.bdpt, c.scale);
}
std::unique_ptr<Integrator> make_sppm(const cl::Context& ctx, const SceneBuffers& s, const Config& c) {
  return std::make_unique<Sppm>(ctx, s, c.sppm, c.scale);
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_table() {
  using F = FilmKind;
  using D = DeviceSplit;
  // name      impl   film            options                          lights persp cap  light  split         make
  static const std::vector<IntegratorInfo> table = {
      {"pt",     true,  F::SampleSums,  OPTIONS_NONE,                    true,  false, 0, false, D::Samples,   make_pt},
      {"lt",     true,  F::Splats,      OPTIONS_NONE,                    true,  true,  0, true,  D::Samples,   make_lt},
      {"bdpt",   true,  F::Splats,      OPTIONS_BDPT | OPTIONS_LVC,      true,  true,  0, false, D::Samples,   make_bdpt},
      {"pm",     true,  F::SampleSums,  OPTIONS_PHOTONS | OPTIONS_PM,    true,  false, 0, false, D::Samples,   make_pm},
      {"sppm",   true,  F::Progressive, OPTIONS_PHOTONS | OPTIONS_SPPM,  true,  false, 0, false, D::OneDevice, make_sppm},
      {"vcm",    true,  F::Splats,      OPTIONS_VCM | OPTIONS_LVC,       true,  true,  0, false, D::Samples,   make_vcm},
      {"mlt",    true,  F::Splats,      OPTIONS_MLT,                     true,  false, 0, false, D::Chains,    make_mlt},
      {"ic",     true,  F::SampleSums,  OPTIONS_IC,                      true,  false, 0, false, D::Samples,   make_ic},
      {"ao",     true,  F::SampleSums,  OPTIONS_AO,                      false, false, 0, false, D::Samples,   make_ao},
      {"direct", true,  F::SampleSums,  OPTIONS_NONE,                    true,  false, 1, false, D::Samples,   make_direct},
      {"indirect1", true, F::SampleSums, OPTIONS_INDIRECT,               true,  false, 2, false, D::Samples,   make_indirect1},
  };
  return table;
}

const IntegratorInfo* find_integrator(const std::string& name) {
  for (const IntegratorInfo& row : integrator_table())
    if (name == row.name) return &row;
  return nullptr;
}

const IntegratorInfo& integrator_info(const std::string& name) {
  const IntegratorInfo* row = find_integrator(name);
  if (!row) throw Error(ExitCode::Usage, "--integrator " + name + ": unknown integrator");
  return *row;
}

dev::PhotonLookup photon_lookup(const PmConfig& pm, const SceneScale& scale) {
  dev::PhotonLookup q{};
  q.knn = std::clamp<uint32_t>(pm.knn, 1, PM_KNN_MAX);
  q.max_radius = pm.max_radius > 0.0f ? pm.max_radius : 0.02f * scale.diagonal;
  q.filter = pm.filter;
  return q;
}

float default_merge_radius(const SceneScale& scale) {
  float r = 2.0f * scale.pixel_footprint;
  if (!(r > 0.0f) || !std::isfinite(r)) r = std::max(1e-3f * scale.diagonal, 1e-6f);
  return r;
}

void VcmStats::add(const VcmStats& o) {
  light_vertices += o.light_vertices;
  connections += o.connections;
  merges += o.merges;
  passes += o.passes;
  grids += o.grids;
  grid_seconds += o.grid_seconds;
  device_bytes += o.device_bytes;
  tiles = std::max(tiles, o.tiles);  // per pass, alike on every device
  alpha = std::max(alpha, o.alpha);  // alike on every device
  pixel_radii = std::max(pixel_radii, o.pixel_radii);
  merge_first = std::max(merge_first, o.merge_first);  // alike on every device
  light_per_pixel = std::max(light_per_pixel, o.light_per_pixel);  // alike on every device
  light_paths_auto = std::max(light_paths_auto, o.light_paths_auto);
  if (pilot.empty()) pilot = o.pilot;  // auto runs on one device only
  if (o.pixel_radius_count) {
    const bool first = pixel_radius_count == 0;
    pixel_radius_min = first ? o.pixel_radius_min : std::min(pixel_radius_min, o.pixel_radius_min);
    pixel_radius_max = first ? o.pixel_radius_max : std::max(pixel_radius_max, o.pixel_radius_max);
    pixel_radius_sum += o.pixel_radius_sum;
    pixel_radius_count += o.pixel_radius_count;
  }
  if (o.passes) {
    // Radii shrink with the sample index: the largest first, the smallest last (passes ==
    // o.passes: this held no pass before, so the other's radii are the only ones).
    first_radius = passes == o.passes ? o.first_radius : std::max(first_radius, o.first_radius);
    last_radius = passes == o.passes ? o.last_radius : std::min(last_radius, o.last_radius);
  }
}

void MetropolisStats::add_chains(const MetropolisStats& o) {
  chains += o.chains;
  large_proposed += o.large_proposed;
  large_accepted += o.large_accepted;
  small_proposed += o.small_proposed;
  small_accepted += o.small_accepted;
  restarts += o.restarts;
  direct_samples += o.direct_samples;
  if (chains_by_depth.size() < o.chains_by_depth.size()) chains_by_depth.resize(o.chains_by_depth.size(), 0);
  for (size_t d = 0; d < o.chains_by_depth.size(); ++d) chains_by_depth[d] += o.chains_by_depth[d];
}

void IcStats::add_lookups(const IcStats& o) {
  lookups += o.lookups;
  records_used += o.records_used;
  misses += o.misses;
}

std::string integrator_names_text(const char* separator, bool implemented_only) {
  std::string text;
  for (const IntegratorInfo& row : integrator_table()) {
    if (implemented_only && !row.implemented) continue;
    if (!text.empty()) text += separator;
    text += row.name;
  }
  return text;
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const cl::Context& ctx,
                                            const SceneBuffers& scene,
                                            const IntegratorConfig& config) {
  const IntegratorInfo& row = integrator_info(name);
  if (!row.make)
    throw Error(ExitCode::Usage, "--integrator " + name + ": not implemented yet (available: " +
                                     integrator_names_text(", ", true) + ")");
  return row.make(ctx, scene, config);
}

}  // namespace clpt
