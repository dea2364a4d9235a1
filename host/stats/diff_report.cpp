#include "stats/diff_report.h"

#include "util/error.h"

namespace clpt {
namespace {

std::string dimensions_text(const Image& i) { return std::to_string(i.width) + "x" + std::to_string(i.height); }

nlohmann::ordered_json input_json(const DiffInput& in, const ImageSummary& summary) {
  nlohmann::ordered_json j;
  j["path"] = in.path;
  j["width"] = in.file.image.width;
  j["height"] = in.file.image.height;
  j["mean"] = summary.finite_mean;  // NaN (no finite value) is written as null
  j["channel_mean"] = summary.channel_finite_mean;
  j["nan"] = summary.nan_count;
  j["inf"] = summary.inf_count;
  j["has_variance"] = in.file.variance() != nullptr;
  const int spp = in.file.int_attribute("clpt:spp", -1);
  j["spp"] = spp >= 0 ? nlohmann::ordered_json(spp) : nlohmann::ordered_json(nullptr);
  return j;
}

}  // namespace

DiffReport diff_images(const DiffInput& image, const DiffInput& reference, const DiffSettings& settings) {
  const Image& v = image.file.image;
  const Image& r = reference.file.image;
  if (v.width != r.width || v.height != r.height)
    throw Error(ExitCode::BadInput, "image " + image.path + " is " + dimensions_text(v) + " but reference " +
                                        reference.path + " is " + dimensions_text(r) + ": the sizes must match");
  DiffReport report;
  report.comparison = compare_images(v, r);
  const Image* var_v = image.file.variance();
  const Image* var_r = reference.file.variance();
  if (var_v || var_r) {
    ZTestOptions zo;
    zo.alpha = settings.alpha;
    zo.relative_variance_floor = settings.variance_floor;
    report.z = z_test(v, var_v, r, var_r, zo);
    report.variance_from = var_v && var_r ? "both" : var_v ? "image" : "reference";
  }
  return report;
}

nlohmann::ordered_json diff_json(const DiffInput& image, const DiffInput& reference, const DiffReport& report,
                                 const DiffSettings& settings) {
  const ImageComparison& cmp = report.comparison;
  nlohmann::ordered_json j;
  j["image"] = input_json(image, cmp.image);
  j["reference"] = input_json(reference, cmp.reference);
  j["compared"] = cmp.compared;
  j["relmse"] = cmp.rel_mse;
  j["mse"] = cmp.mse;
  j["rmse"] = cmp.rmse;
  j["smape"] = cmp.smape;
  j["max_abs_diff"] = cmp.max_abs_diff;
  if (const auto& z = report.z) {
    j["z_test"] = {{"variance_from", report.variance_from},
                   {"tested", z->tested},
                   {"passed", z->passed},
                   {"failed", z->failed()},
                   {"skipped", z->skipped},
                   {"pass_fraction", z->pass_fraction()},
                   {"threshold", z->threshold},
                   {"alpha", z->alpha},
                   {"max_abs_z", z->max_abs_z},
                   {"variance_floor", settings.variance_floor}};
  } else {
    j["z_test"] = nullptr;
  }
  return j;
}

}  // namespace clpt
