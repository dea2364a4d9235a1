#include "support/split_render.h"

#include <gtest/gtest.h>

#include "stats/image_stats.h"

namespace clpt::test {

void TestFolder::make_folder(const std::string& prefix) {
  dir_ = std::filesystem::temp_directory_path() /
         (prefix + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

void TestFolder::TearDown() {
  if (!dir_.empty() && !HasFailure()) std::filesystem::remove_all(dir_);
}

Agreement agreement(const Image& a, const Image& b) {
  return {compare_images(a, b).rel_mse, image_mean(a) / image_mean(b)};
}

void expect_device_shares(const nlohmann::json& stats, size_t devices, uint64_t spp) {
  ASSERT_EQ(stats["devices"].size(), devices) << stats["devices"].dump();
  uint64_t total = 0;
  for (const auto& d : stats["devices"]) {
    EXPECT_GT(d["samples_per_pixel"].get<uint64_t>(), 0u) << stats["devices"].dump();
    EXPECT_GT(d["paths_per_second"].get<double>(), 0.0);
    total += d["samples_per_pixel"].get<uint64_t>();
  }
  EXPECT_EQ(total, spp);
}

}  // namespace clpt::test
