// ImageReader (host/io/image_io.*): the reader behind --env, --reference and clpt-diff on the
// malformed image corpus (tests/data/malformed-images/README.md has the same table).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "util/error.h"

namespace clpt::image_reader_test {
namespace {

namespace fs = std::filesystem;

// File -> a fragment of its error message, or "" for a file that must be read.
const std::map<std::string, std::string> kCases = {
    {"lying_8000.hdr", "cannot read scanlines 0..63 of 8000"},
    {"huge_16000.hdr", "the image is 16000x16000, larger than the limit"},
    {"lying_window.exr", "cannot read image: OpenEXR exception"},
    {"empty.exr", "the file is empty"},
    {"wide_window.exr", "the image is 1048577x1, larger than the limit"},
    {"chlist_size_lies.exr", "damaged EXR: attribute 'channels' (chlist) of 75 bytes does not hold a value of its type"},
    {"huge_attribute.exr", "damaged EXR: attribute 'compression' (compression) claims 1879048192 bytes, past the end"},
    {"tiff_named.exr", "not an OpenEXR, Radiance HDR, PNG or JPEG image"},
    {"truncated_png_named.hdr", "truncated PNG: chunk 9 at byte 275 is cut off"},
    {"premature_end.jpg", "cannot read scanlines 0..63 of 256: JPEG error: Corrupt JPEG data: premature end"},
    {"cut_in_marker.jpg", "damaged JPEG: the segment of marker 226 at byte 2 claims 188 bytes"},
    {"damaged_icc_profile.jpg", ""},
    {"newline_in_channel_name.exr", "' is subsampled, which clpt does not read"},
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

// The EXR header walk (check_exr_headers) must let real files through: a multi-part EXR of two
// parts written by OpenImageIO (OpenEXR's multi-part layout: headers until an empty one) reads
// as its first part.
TEST(ImageReader, MultiPartExrReads) {
  const fs::path file = fs::temp_directory_path() / ("clpt-multipart-" + std::to_string(::getpid()) + ".exr");
  {
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->supports("multiimage"));
    OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(4, 3, 3, OIIO::TypeDesc::FLOAT),
                                OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT)};
    specs[0].attribute("name", "first");
    specs[1].attribute("name", "second");
    specs[1].full_width = 4, specs[1].full_height = 3;  // one display window for all parts
    const bool opened = out->open(file.string(), 2, specs);
    ASSERT_TRUE(opened) << out->geterror() << OIIO::geterror();
    std::vector<float> a(4 * 3 * 3, 0.25f), b(2 * 2 * 3, 0.5f);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, a.data()));
    ASSERT_TRUE(out->open(file.string(), specs[1], OIIO::ImageOutput::AppendSubimage));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, b.data()));
    out->close();
  }
  {
    std::ifstream f(file, std::ios::binary);
    unsigned char head[8] = {};
    f.read(reinterpret_cast<char*>(head), 8);
    ASSERT_TRUE(head[5] & 0x10) << "not written as a multi-part file (version flag 0x1000)";
  }
  const Image img = read_image(file);
  fs::remove(file);
  EXPECT_EQ(img.width, 4u);
  EXPECT_EQ(img.height, 3u);
  EXPECT_FLOAT_EQ(img.rgb[0], 0.25f);
}

}  // namespace
}  // namespace clpt::image_reader_test
