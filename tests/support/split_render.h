// Renders split over devices or MPI ranks against one device's (tests/multi_device_test.cpp,
// tests/mpi_test.cpp): how closely the images agree, and the shares --stats reports.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/image.h"

namespace clpt::test {

// A test with a folder of its own under the temporary directory, named PREFIX-TEST, made by
// make_folder() and removed after the test unless it failed (its files are then kept).
class TestFolder : public ::testing::Test {
 protected:
  void make_folder(const std::string& prefix);
  void TearDown() override;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
};

struct Agreement {
  double rel_mse = 0.0;     // stats/image_stats.h's relMSE of a against b
  double mean_ratio = 1.0;  // mean of a over mean of b
};

Agreement agreement(const Image& a, const Image& b);

// The --stats document's "devices": `devices` entries, each of which took samples and traced
// paths, their samples per pixel adding up to `spp` (gtest expectations).
void expect_device_shares(const nlohmann::json& stats, size_t devices, uint64_t spp);

}  // namespace clpt::test
