// ImageReader (host/io/image_io.*): the reader behind --env, --reference and clpt-diff on the
// malformed image corpus (tests/data/malformed-images/README.md has the same table).
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "io/image_io.h"
#include "util/error.h"

namespace clpt {
namespace {

namespace fs = std::filesystem;

// File -> a fragment of its error message, or "" for a file that must be read.
const std::map<std::string, std::string> kCases = {
    {"lying_8000.hdr", "cannot read scanlines 0..63 of 8000"},
    {"huge_16000.hdr", "the image is 16000x16000, larger than the limit"},
    {"lying_window.exr", "cannot read image: OpenEXR exception"},
    {"empty.exr", "the file is empty"},
    {"tiff_named.exr", "not an OpenEXR, Radiance HDR, PNG or JPEG image"},
    {"truncated_png_named.hdr", "truncated PNG: chunk 9 at byte 275 is cut off"},
    {"cut_in_marker.jpg", "damaged JPEG: the segment of marker 226 at byte 2 claims 188 bytes"},
    {"damaged_icc_profile.jpg", ""},
};

TEST(ImageReader, MalformedCorpus) {
  const fs::path dir = fs::path(CLPT_TEST_DATA_DIR) / "malformed-images";
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name == "README.md") continue;
    ++files;
    SCOPED_TRACE(name);
    const auto c = kCases.find(name);
    ASSERT_NE(c, kCases.end()) << "a file in the corpus that the test's table does not list";
    if (c->second.empty()) {
      const ImageChannels img = read_image_channels(entry.path());
      EXPECT_EQ(img.image.width, 8u);
      EXPECT_EQ(img.image.height, 8u);
      continue;
    }
    try {
      read_image_channels(entry.path());
      ADD_FAILURE() << "read, but the corpus says it is refused";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(e.code(), ExitCode::BadInput) << m;
      EXPECT_EQ(m.rfind(entry.path().string() + ": ", 0), 0u) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_NE(m.find(c->second), std::string::npos) << m;
    }
  }
  EXPECT_EQ(files, kCases.size()) << "a file of the table is missing from the corpus";
}

}  // namespace
}  // namespace clpt
