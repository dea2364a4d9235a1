// The on-disk cache of pt references shared by test processes (support/reference_render.h):
// what it returns must be what rendering returns, whether it rendered, read its entry, or
// found the entry damaged.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render/renderer.h"
#include "support/device.h"
#include "support/reference_render.h"
#include "support/scenes.h"

namespace clpt::reference_render_test {
namespace {

void expect_same(const FilmResult& a, const FilmResult& b, const char* what) {
  EXPECT_EQ(a.mean.width, b.mean.width) << what;
  EXPECT_EQ(a.mean.rgb, b.mean.rgb) << what;
  EXPECT_EQ(a.variance.rgb, b.variance.rgb) << what;
  EXPECT_EQ(a.samples_per_pixel, b.samples_per_pixel) << what;
  EXPECT_EQ(a.rays, b.rays) << what;
}

TEST(ReferenceRender, CachedEqualsRendered) {
  // A size, spp and seed no other test uses, so this test owns the entry.
  const auto scene = test::ReferenceScene::CornellBox;
  const uint32_t size = 8, seed = 97;
  const uint64_t spp = 16;
  const std::filesystem::path file = test::pt_reference_file(scene, size, spp, seed);
  if (file.empty()) GTEST_SKIP() << "no cache directory (XDG_CACHE_HOME, HOME unset)";
  std::filesystem::remove(file);

  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.seed = seed;
  const FilmResult direct = Renderer(test::device_context(), test::cornell_box(), s).render().film;

  expect_same(test::pt_reference(scene, size, spp, seed), direct, "first call (renders)");
  ASSERT_TRUE(std::filesystem::exists(file)) << file;
  expect_same(test::pt_reference(scene, size, spp, seed), direct, "second call (reads)");

  // A flipped byte in the image: the entry's checksum fails, so it renders again.
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(100);
    const char c = char(f.get());
    f.seekp(100);
    f.put(char(c ^ 0x5a));
  }
  expect_same(test::pt_reference(scene, size, spp, seed), direct, "damaged entry");
  // A truncated one, likewise.
  std::filesystem::resize_file(file, 64);
  expect_same(test::pt_reference(scene, size, spp, seed), direct, "truncated entry");
  EXPECT_GT(std::filesystem::file_size(file), 64u) << "the entry is written again";
}

}  // namespace
}  // namespace clpt::reference_render_test
