// BDPT's recursive MIS weights (kernels/integrators/stages/vertex_mis.cl; Georgiev 2012 without
// merging) against the weights written out from whole-path densities, on the PoCL device
// through tests/kernels/bdpt_mis_test.cl:
//   BdptMis.RecursiveEqualsExplicit  for random complete paths of 2..6 edges sampled from the
//       camera to an emitter (diffuse Cornell box; a glossy one: metal walls and a glossy
//       coat, roughness 0.3; the Cornell box with a rough glass sphere), each strategy's
//       recursive weight (the integrator's calls replayed over the path's own vertices)
//       equals (n_i p_i)^b / sum_j (n_j p_j)^b from the per-vertex area densities, the
//       weights of a path sum to 1, for the power (b = 2) and balance (b = 1) heuristics;
//       and with vertex merging (vcm's weights, Georgiev 2012; the *_vcm cases, eta =
//       pi r^2 N_light of about 0.4, where merges and connections both take a share) every
//       connection strategy's and every merge's (at x_1 .. x_(m-1)) recursive weight equals
//       the explicit one, and all of them together sum to 1: MIS's partition of unity over
//       both techniques. The *_vcm_first cases (--vcm-merge first) merge at x_1 alone: the
//       explicit weights count that merge only, and the recursive ones must agree.
//
// Conventions (pbrt's; mis.cl's header): x0 the pinhole, xm on the light; strategy (s, t)
// takes s vertices from the light end and t from the camera end, s + t = m + 1. For m >= 2
// the strategies are s = 0 .. m (t = 1: light tracing); s = m + 1 (t = 0) cannot hit a
// pinhole. Camera strategies take one sample per pixel, with x1's density per pixel
// (width * height times the whole film's); light tracing takes N_light = K width * height
// light paths per pixel sample (K = 1 but for the *_light_paths cases: vcm's --vcm-light-paths K).
// The strategy (1, 1), left out by the integrator, exists only
// for m = 1, which has the single strategy (0, 2) and is not sampled here. Merging at x_k
// takes the camera subpath's x_1 .. x_k and the light subpath's x_m .. x_k; its density is a
// connection's times pi r^2 N_merge times the light subpath's density of x_k (eta times the
// product of both subpaths' densities).
//
// Every distance, direction and density is recomputed from the vertex positions for both
// sides, so the two computations see the same numbers and agree to float rounding (about
// 1e-6). A second figure line shows the weights with the camera subpath's own hit.t, ray
// direction and bs.pdf_w, as the integrator first fed bdpt_mis_arrive / bdpt_mis_scatter:
// those are measured from the offset ray origin (kernels/core/ray.cl), so on edges only a
// few offsets long (paths into a corner) the weights summed to 1 only to about 1e-3
// (diffuse) or a few 1e-2 (glossy). This test found that; the integrator now passes
// vertex-to-vertex distances, and the sampled bs.pdf_w (the remaining, smaller part: it
// matters only on edges about 1e-4 long) is still the ray's. Reported, not asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bvh/bvh.h"
#include "render/camera_setup.h"
#include "render/scene_buffers.h"
#include "support/device.h"
#include "support/mesh.h"
#include "support/scenes.h"

namespace clpt::bdpt_mis_test {
namespace {

constexpr int kSlots = 8;      // MIS_TEST_SLOTS
constexpr int kMaxEdges = 6;   // MIS_TEST_MAX_EDGES
constexpr int kStatusOk = 1, kStatusCameraInvalid = 2, kStatusNoLightPdf = 3;
constexpr uint32_t kPaths = 1u << 17;
constexpr uint32_t kWidth = 40, kHeight = 30;  // N_light = 1200: light tracing gets weight
constexpr size_t kMinPerLength = 100;          // paths of each length 2..5
// vcm's eta = pi r^2 N_light for r = 0.01 (the box is 0.55 wide): merges and connections
// both take a share of the paths of 3 and more edges.
constexpr float kEta = 3.14159265f * 0.01f * 0.01f * float(kWidth * kHeight);

const cl::Program& mis_program() {
  return test::test_program("kernels/bdpt_mis_test.cl");
}

// The Cornell box with its red and green walls metal (roughness 0.3) and its white surfaces
// a dielectric coat over the diffuse base (specular 1, roughness 0.3): multi-lobe mixtures.
Scene glossy_box() {
  Scene s = test::cornell_box();
  for (Material& m : s.materials) {
    if (glm::length(m.emission) > 0.0f) continue;
    m.roughness = 0.3f;
    if (m.name == "white") {
      m.metallic = 0.0f;
      m.specular = 1.0f;
    } else {
      m.metallic = 1.0f;
    }
  }
  return s;
}

// The Cornell box whose white surfaces have a KHR_materials_clearcoat (weight 0.7, its
// textures' values included: not a multiple of 1/65535, so the PathVertex's 16-bit storage
// must round as material_resolve does) over a rough red-white coat: four-lobe mixtures.
Scene clearcoat_box() {
  Scene s = glossy_box();
  for (Material& m : s.materials)
    if (m.name == "white") {
      m.clearcoat = 0.7f;
      m.clearcoat_roughness = 0.23f;
    }
  return s;
}

// The Cornell box with a rough glass sphere (roughness 0.3, flat facets) floating in the
// middle: paths refract, so a vertex's camera-side and light-side orientations differ.
Scene glass_sphere_box() {
  Scene s = test::cornell_box();
  Material glass;
  glass.name = "rough_glass";
  glass.base_color = glm::vec4(1.0f);
  glass.metallic = 0.0f;
  glass.roughness = 0.3f;
  glass.transmission = 1.0f;
  glass.specular = 1.0f;
  glass.ior = 1.5f;
  glass.double_sided = true;
  test::add_mesh(s, test::icosphere(glm::vec3(0.278f, 0.42f, 0.25f), 0.08f, 2), glass);
  return s;
}

// The glass sphere box with a KHR_materials_iridescence film on the sphere: the film sets the
// split between reflection and refraction that both subpaths' pdfs must agree on, from
// either side of the glass, and a PathVertex must carry it to the light side's connections.
Scene iridescent_sphere_box() {
  Scene s = glass_sphere_box();
  for (Material& m : s.materials)
    if (m.name == "rough_glass") {
      m.iridescence = 0.8f;
      m.iridescence_ior = 1.7f;
      m.iridescence_thickness_max = 380.0f;
    }
  return s;
}

struct MisCase {
  const char* name;
  Scene (*scene)();
  uint32_t heuristic;       // dev::MIS_POWER or dev::MIS_BALANCE
  size_t min_refracting;    // paths that must pass through a surface (the glass sphere)
  float eta = 0.0f;         // vcm: pi r^2 N_merge; 0: bdpt (no merging)
  // > 0: the light subpaths are traced with this eta and moved to eta's by their EtaSlopes
  // (vcm's --vcm-shrink pixel); 0: traced with eta.
  float eta_traced = 0.0f;
  bool merge_first = false;  // vcm's --vcm-merge first: merging at x_1 alone (every vertex here
                             // has a non-delta lobe)
  uint32_t light_per_pixel = 1;  // vcm's --vcm-light-paths: N_light = this times width * height
};
void PrintTo(const MisCase& c, std::ostream* os) { *os << c.name; }

struct PathRecords {
  std::vector<float> rec, rec_raw, rec_vm, pcam, plight;
  std::vector<int> meta;
};

PathRecords run_paths(const Scene& scene, uint32_t heuristic, float eta, float eta_traced,
                      bool merge_first, uint32_t light_per_pixel) {
  cl::Context& ctx = test::device_context();
  const Bvh bvh = build_bvh(scene.positions, scene.triangles);
  const FlatScene flat = flatten_scene(scene, bvh);
  const SceneBuffers buffers(ctx, flat);
  dev::RenderParams p{};
  p.camera = camera_data(choose_camera(scene, ""), kWidth, kHeight);
  set_thin_lens(p.camera, 0.0f, 0.0f, scene.bounds());
  p.width = kWidth;
  p.height = kHeight;
  p.max_depth = 8;
  p.rr_depth = 1000;
  p.seed = 17;
  p.sampler = dev::SAMPLER_INDEPENDENT;
  p.mis = heuristic;
  p.light_samples = 1;
  p.branching = 1;
  cl::Buffer params = cl::Buffer::from_vector(ctx, std::vector<dev::RenderParams>{p});
  const size_t floats = size_t(kPaths) * kSlots;
  cl::Buffer rec(ctx, floats * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "rec");
  cl::Buffer rec_raw(ctx, floats * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "rec_raw");
  cl::Buffer rec_vm(ctx, floats * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "rec_vm");
  cl::Buffer pcam(ctx, floats * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "pcam");
  cl::Buffer plight(ctx, floats * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "plight");
  cl::Buffer meta(ctx, size_t(kPaths) * 4 * sizeof(int), CL_MEM_WRITE_ONLY, nullptr, "meta");
  cl::Kernel k(mis_program(), "bdpt_mis_paths");
  const cl_uint a = buffers.bind(k, 0);
  k.args(a, params, kPaths, eta, eta_traced, cl_int(merge_first ? 1 : 0), float(light_per_pixel), rec,
         rec_raw, rec_vm, pcam,
         plight, meta);
  k.launch(ctx, kPaths);
  return {rec.read_vector<float>(floats), rec_raw.read_vector<float>(floats),
          rec_vm.read_vector<float>(floats), pcam.read_vector<float>(floats),
          plight.read_vector<float>(floats), meta.read_vector<int>(size_t(kPaths) * 4)};
}

// The explicit weights of path (m, pcam, plight): strategy s has density
//   prod_{i=1}^{t-1} pcam_i (pcam_1 per pixel: `pixels` times the film's) *
//   prod_{j=m-s+1}^{m} plight_j,  t = m + 1 - s,
// with n = N_light samples for t = 1 and 1 otherwise; with eta > 0 also merging at x_k,
// k = 1 .. m - 1 (in vm[k]; k = 1 alone with merge_first), n p = eta prod_{i=1}^{k} pcam_i
// prod_{j=k}^{m} plight_j.
struct ExplicitWeights {
  std::array<double, kSlots> vc{}, vm{};
};
ExplicitWeights explicit_weights(int m, const float* pcam, const float* plight, double pixels,
                                 double n_light, double exponent, double eta, bool merge_first) {
  ExplicitWeights w;
  double sum = 0.0;
  const auto camera_prefix = [&](int last) {
    double p = 1.0;
    for (int i = 1; i <= last; ++i) p *= i == 1 ? pixels * double(pcam[1]) : double(pcam[i]);
    return p;
  };
  const auto light_suffix = [&](int first) {
    double p = 1.0;
    for (int j = first; j <= m; ++j) p *= double(plight[j]);
    return p;
  };
  for (int s = 0; s <= m; ++s) {
    const int t = m + 1 - s;
    const double n = t == 1 ? n_light : 1.0;
    w.vc[s] = std::pow(n * camera_prefix(t - 1) * light_suffix(m - s + 1), exponent);
    sum += w.vc[s];
  }
  if (eta > 0.0)
    for (int k = 1; k <= (merge_first ? 1 : m - 1); ++k) {
      w.vm[k] = std::pow(eta * camera_prefix(k) * light_suffix(k), exponent);
      sum += w.vm[k];
    }
  for (int s = 0; s <= m; ++s) w.vc[s] /= sum;
  for (int k = 1; k <= m - 1; ++k) w.vm[k] /= sum;
  return w;
}

class BdptMis : public ::testing::TestWithParam<MisCase> {};

TEST_P(BdptMis, RecursiveEqualsExplicit) {
  const MisCase& c = GetParam();
  const PathRecords r =
      run_paths(c.scene(), c.heuristic, c.eta, c.eta_traced, c.merge_first, c.light_per_pixel);
  const double pixels = double(kWidth) * kHeight, n_light = pixels * c.light_per_pixel;
  const double exponent = c.heuristic == dev::MIS_BALANCE ? 1.0 : 2.0;

  std::array<size_t, kMaxEdges + 1> per_length{};
  std::array<double, kSlots> mean_weight{};  // of paths of 4 edges, by s
  double mean_merge_weight = 0.0;            // ... and of all their merges together
  size_t ok = 0, camera_invalid = 0, no_light_pdf = 0, failures = 0, checked = 0, refracting = 0;
  double max_abs = 0.0, max_rel = 0.0, max_sum_dev = 0.0;
  // The integrator's own inputs (rec_raw): hit.t, ray directions, bs.pdf_w.
  double raw_max_abs = 0.0, raw_max_sum_dev = 0.0, max_dt = 0.0, max_dpdf = 0.0;
  for (uint32_t i = 0; i < kPaths; ++i) {
    const int m = r.meta[4 * i], status = r.meta[4 * i + 1];
    camera_invalid += status == kStatusCameraInvalid;
    no_light_pdf += status == kStatusNoLightPdf;
    if (status != kStatusOk) continue;
    ++ok;
    ASSERT_GE(m, 2);
    ASSERT_LE(m, kMaxEdges);
    ++per_length[m];
    refracting += r.meta[4 * i + 2] > 0;
    const float* rec = &r.rec[size_t(i) * kSlots];
    const float* raw = &r.rec_raw[size_t(i) * kSlots];
    const float* pc = &r.pcam[size_t(i) * kSlots];
    const float* pl = &r.plight[size_t(i) * kSlots];
    max_dt = std::max(max_dt, double(pc[0]));
    max_dpdf = std::max(max_dpdf, double(pl[0]));
    const float* vm = &r.rec_vm[size_t(i) * kSlots];
    const ExplicitWeights w =
        explicit_weights(m, pc, pl, pixels, n_light, exponent, c.eta, c.merge_first);
    double sum = 0.0, raw_sum = 0.0;
    // One weight against its explicit value; `what` names the technique for the report.
    const auto check = [&](float recursive, double expected, const std::string& what) {
      ++checked;
      const double abs_dev = std::fabs(double(recursive) - expected);
      max_abs = std::max(max_abs, abs_dev);
      if (expected > 1e-3) max_rel = std::max(max_rel, abs_dev / expected);
      const bool bad = !std::isfinite(recursive) || (abs_dev > 1e-3 * expected && abs_dev > 1e-5);
      if (bad && ++failures <= 10) {
        std::ostringstream os;
        os << "path " << i << ", m = " << m << ", " << what << ": recursive " << recursive
           << ", explicit " << expected << "\n  pcam:";
        for (int j = 1; j <= m; ++j) os << " " << pc[j];
        os << "\n  plight:";
        for (int j = 1; j <= m; ++j) os << " " << pl[j];
        os << "\n  recursive:";
        for (int t = 0; t <= m; ++t) os << " " << rec[t];
        os << "\n  explicit: ";
        for (int t = 0; t <= m; ++t) os << " " << w.vc[t];
        ADD_FAILURE() << os.str();
      }
    };
    for (int s = 0; s <= m; ++s) {
      sum += rec[s];
      raw_sum += raw[s];
      if (m == 4) mean_weight[s] += rec[s];
      raw_max_abs = std::max(raw_max_abs, std::fabs(double(raw[s]) - w.vc[s]));
      check(rec[s], w.vc[s], "strategy s = " + std::to_string(s) + " t = " + std::to_string(m + 1 - s));
    }
    if (c.eta > 0.0f)
      for (int k = 1; k <= m - 1; ++k) {
        sum += vm[k];
        if (m == 4) mean_merge_weight += vm[k];
        check(vm[k], w.vm[k], "merge at x_" + std::to_string(k));
      }
    max_sum_dev = std::max(max_sum_dev, std::fabs(sum - 1.0));
    raw_max_sum_dev = std::max(raw_max_sum_dev, std::fabs(raw_sum - 1.0));
    if (!(std::fabs(sum - 1.0) <= 1e-4) && ++failures <= 10)
      ADD_FAILURE() << "path " << i << ", m = " << m << ": recursive weights sum to " << sum;
  }

  std::ostringstream fig;
  fig << "[ figures  ] " << c.name << ": " << ok << " paths (by edges 2..6:";
  for (int m = 2; m <= kMaxEdges; ++m) fig << " " << per_length[m];
  fig << "; " << refracting << " through a surface), " << checked << " weights, max |rec - explicit| " << max_abs
      << ", max rel (explicit > 1e-3) " << max_rel << ", max |sum - 1| " << max_sum_dev
      << "; mean weight by s = 0..4 at 4 edges:";
  for (int s = 0; s <= 4; ++s) fig << " " << (per_length[4] ? mean_weight[s] / per_length[4] : 0.0);
  if (c.eta > 0.0f)
    fig << ", merges " << (per_length[4] ? mean_merge_weight / per_length[4] : 0.0) << " (eta "
        << c.eta << ")";
  fig << "; skipped: camera_connect invalid " << camera_invalid << ", no light pdf " << no_light_pdf;
  std::cout << fig.str() << "\n";
  if (c.eta == 0.0f)  // rec_raw holds the connection strategies only
    std::cout << "[ figures  ] " << c.name << " with the ray's hit.t and bs.pdf_w: max |rec - explicit| "
            << raw_max_abs << ", max |sum - 1| " << raw_max_sum_dev << " (inputs off by up to "
            << max_dt << " in distance, " << max_dpdf << " in pdf, relative)\n";

  EXPECT_EQ(failures, 0u) << "weights that differ (first 10 reported above)";
  EXPECT_EQ(no_light_pdf, 0u);
  EXPECT_LE(camera_invalid, kPaths / 1000);
  for (int m = 2; m <= 5; ++m)
    EXPECT_GE(per_length[m], kMinPerLength) << "too few paths of " << m << " edges";
  EXPECT_GE(refracting, c.min_refracting) << "too few paths through the glass";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BdptMis,
    ::testing::Values(MisCase{"cornell_power", test::cornell_box, dev::MIS_POWER, 0},
                      MisCase{"cornell_balance", test::cornell_box, dev::MIS_BALANCE, 0},
                      MisCase{"glossy_power", glossy_box, dev::MIS_POWER, 0},
                      MisCase{"glossy_balance", glossy_box, dev::MIS_BALANCE, 0},
                      MisCase{"clearcoat_power", clearcoat_box, dev::MIS_POWER, 0},
                      MisCase{"clearcoat_balance_vcm", clearcoat_box, dev::MIS_BALANCE, 0, kEta},
                      MisCase{"glass_sphere_power", glass_sphere_box, dev::MIS_POWER, 100},
                      MisCase{"glass_sphere_balance", glass_sphere_box, dev::MIS_BALANCE, 100},
                      MisCase{"iridescent_sphere_power", iridescent_sphere_box, dev::MIS_POWER, 100},
                      MisCase{"cornell_power_vcm", test::cornell_box, dev::MIS_POWER, 0, kEta},
                      MisCase{"glossy_balance_vcm", glossy_box, dev::MIS_BALANCE, 0, kEta},
                      MisCase{"glass_sphere_power_vcm", glass_sphere_box, dev::MIS_POWER, 100, kEta},
                      // Traced with another eta and rebased (per-pixel radii): 9 times and a
                      // fifth of the one the weights are checked for.
                      MisCase{"cornell_power_vcm_rebased", test::cornell_box, dev::MIS_POWER, 0, kEta,
                              9.0f * kEta},
                      MisCase{"glossy_balance_vcm_rebased", glossy_box, dev::MIS_BALANCE, 0, kEta,
                              0.2f * kEta},
                      // Merging at the first camera vertex alone (--vcm-merge first), also
                      // rebased and through the glass.
                      MisCase{"cornell_power_vcm_first", test::cornell_box, dev::MIS_POWER, 0, kEta,
                              0.0f, true},
                      MisCase{"glossy_balance_vcm_first_rebased", glossy_box, dev::MIS_BALANCE, 0,
                              kEta, 9.0f * kEta, true},
                      MisCase{"glass_sphere_power_vcm_first", glass_sphere_box, dev::MIS_POWER, 100,
                              kEta, 0.0f, true},
                      // Three light subpaths per pixel (--vcm-light-paths 3): light tracing's
                      // N_light and eta three times as large, rebased as with per-pixel radii.
                      MisCase{"glossy_power_vcm_first_3_light_paths", glossy_box, dev::MIS_POWER, 0,
                              3.0f * kEta, 2.0f * kEta, true, 3},
                      MisCase{"glass_sphere_balance_vcm_3_light_paths", glass_sphere_box,
                              dev::MIS_BALANCE, 100, 3.0f * kEta, 0.0f, false, 3}),
    [](const ::testing::TestParamInfo<MisCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clpt::bdpt_mis_test
