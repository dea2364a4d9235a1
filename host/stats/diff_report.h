// What clpt-diff reports on an image against a reference, as data and as its --json
// document; clpt-diff prints it, the Python module's clpt.diff returns it as a dictionary.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "io/image_io.h"
#include "stats/image_stats.h"

namespace clpt {

struct DiffSettings {
  double alpha = 0.01;                             // family-wise significance of the z-test
  double variance_floor = kRelativeVarianceFloor;  // z-test variance floor (ZTestOptions)
};

// One side of a comparison: the image, its layers (a "variance" layer enables the z-test)
// and its metadata (clpt:spp is reported), named by `path` (any label for in-memory images).
struct DiffInput {
  std::string path;
  ImageChannels file;
};

struct DiffReport {
  ImageComparison comparison;
  std::optional<ZTestResult> z;  // when either side has a variance layer
  std::string variance_from;     // "both", "image", "reference"; empty without a z-test
};

// Throws Error(BadInput) naming both inputs when their sizes differ.
DiffReport diff_images(const DiffInput& image, const DiffInput& reference, const DiffSettings& settings = {});

// clpt-diff --json's document without its checks: "image", "reference", "compared",
// "relmse", "mse", "rmse", "smape", "max_abs_diff", "z_test" (null without a variance).
nlohmann::ordered_json diff_json(const DiffInput& image, const DiffInput& reference, const DiffReport& report,
                                 const DiffSettings& settings = {});

}  // namespace clpt
