// ImageCodecs (host/io/*_codec, behind io/image_io and scene/image_decode): clpt's decoders and
// writers against OpenImageIO, an independent reader and writer of the same formats (clpt's
// own image I/O until session 43). Every PNG, JPEG and WebP texture of ../shared decodes to
// OpenImageIO's texels; Radiance HDR and OpenEXR files OpenImageIO writes (run-length and
// flat HDR rows; half and float EXR channels, a data window away from the origin, layers) read
// to its values; what clpt writes reads back in OpenImageIO with its pixels and metadata; and
// every prefix of a valid file is refused or read without a crash (the sanitizer suite runs
// this suite too).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "io/exr_codec.h"
#include "io/hdr_codec.h"
#include "io/image_io.h"
#include "io/jpeg_codec.h"
#include "io/png_codec.h"
#include "io/webp_codec.h"
#include "scene/image_decode.h"
#include "util/error.h"

namespace clpt::image_codecs_test {
namespace {

namespace fs = std::filesystem;

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("clpt-codecs-" + std::to_string(::getpid()) + "-" + name);
}

std::vector<unsigned char> file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// OpenImageIO's RGBA texels of a texture, as clpt's texture decoder defines them: grey to RGB,
// a missing alpha opaque, alpha straight. 8 or 16 bits per channel.
bool oiio_texels(const fs::path& file, bool wide, std::vector<uint32_t>* out, uint32_t* w, uint32_t* h) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(file.string(), &config);
  if (!in) return false;
  const OIIO::ImageSpec& s = in->spec();
  *w = uint32_t(s.width);
  *h = uint32_t(s.height);
  const int nc = std::min(s.nchannels, 4);
  const size_t n = size_t(s.width) * size_t(s.height);
  std::vector<uint16_t> px16(wide ? n * size_t(nc) : 0);
  std::vector<unsigned char> px8(wide ? 0 : n * size_t(nc));
  if (!in->read_image(0, 0, 0, nc, wide ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8,
                      wide ? static_cast<void*>(px16.data()) : static_cast<void*>(px8.data())))
    return false;
  out->assign(n * (wide ? 2 : 1), 0);
  const uint32_t opaque = wide ? 65535u : 255u;
  for (size_t i = 0; i < n; ++i) {
    uint32_t c[4] = {0, 0, 0, opaque};
    for (int k = 0; k < nc; ++k) c[k] = wide ? px16[i * size_t(nc) + size_t(k)] : px8[i * size_t(nc) + size_t(k)];
    if (nc <= 2) {
      if (nc == 2) c[3] = c[1];
      c[1] = c[2] = c[0];
    }
    if (wide) {
      (*out)[2 * i] = c[0] | c[1] << 16;
      (*out)[2 * i + 1] = c[2] | c[3] << 16;
    } else {
      (*out)[i] = c[0] | c[1] << 8 | c[2] << 16 | c[3] << 24;
    }
  }
  return true;
}

std::vector<fs::path> shared_textures() {
  std::vector<fs::path> files;
  for (const fs::path& root : {fs::path(CLPT_SHARED_SCENES_DIR), fs::path(CLPT_SHARED_EXTENSIONS_DIR)}) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(root, ec); it != fs::recursive_directory_iterator(); ++it) {
      std::string ext = it->path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
      if (it->is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".webp"))
        files.push_back(it->path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Decodes `bytes` (the file `file`) with clpt's texture decoder and with OpenImageIO, and
// expects the same size and texels; returns clpt's image (texels empty where decoding failed).
DecodedImage expect_texels_as_oiio(const fs::path& file, const std::vector<unsigned char>& bytes, bool keep16) {
  DecodedImage mine;
  std::string why;
  if (!decode_image(bytes.data(), bytes.size(), &mine, &why, kMaxImageDimension, kMaxImagePixels, keep16)) {
    ADD_FAILURE() << why;
    return {};
  }
  std::vector<uint32_t> theirs;
  uint32_t w = 0, h = 0;
  if (!oiio_texels(file, mine.wide, &theirs, &w, &h)) {
    ADD_FAILURE() << "OpenImageIO: " << OIIO::geterror();
    return {};
  }
  EXPECT_EQ(mine.width, w);
  EXPECT_EQ(mine.height, h);
  if (mine.texels.size() != theirs.size()) {
    ADD_FAILURE() << mine.texels.size() << " texel words against OpenImageIO's " << theirs.size();
    return mine;
  }
  size_t differ = 0, first = 0;
  for (size_t i = 0; i < theirs.size(); ++i)
    if (mine.texels[i] != theirs[i] && differ++ == 0) first = i;
  EXPECT_EQ(differ, 0u) << "texel words differ, the first at " << first << ": " << std::hex << mine.texels[first]
                        << " against OpenImageIO's " << theirs[first];
  return mine;
}

// Every texture of ../shared: clpt's texels are OpenImageIO's, bit for bit, at 8 bits and (for
// 16-bit PNGs) at 16. (Its own suite: the integration tier's, and not the sanitizer suite's.)
TEST(SharedTextures, DecodeAsOpenImageIODecodesThem) {
  const std::vector<fs::path> files = shared_textures();
  if (files.empty()) GTEST_SKIP() << "../shared/scenes and ../shared/scenes-extensions absent";
  size_t compared = 0, wide = 0;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    const std::vector<unsigned char> bytes = file_bytes(file);
    // 16 bits where the file has them, then (for those) 8: an 8-bit file decodes once.
    for (const bool keep16 : {true, false}) {
      const DecodedImage mine = expect_texels_as_oiio(file, bytes, keep16);
      if (mine.texels.empty()) break;  // the failure is reported
      ++compared;
      wide += mine.wide;
      if (!mine.wide) break;
    }
  }
  RecordProperty("images", int(compared));
  RecordProperty("wide", int(wide));
  EXPECT_GT(compared, 20u);
}

// 16-bit PNGs (none among ../shared's textures): grey, grey and alpha, RGB and RGBA that
// OpenImageIO writes decode to its 16-bit texels kept, and to its 8-bit ones rounded.
TEST(ImageCodecs, SixteenBitPngsDecodeAsOpenImageIODecodesThem) {
  std::mt19937 rng(11);
  for (const int nc : {1, 2, 3, 4}) {
    SCOPED_TRACE(nc);
    const int w = 7, h = 69;
    std::vector<uint16_t> px(size_t(w) * h * size_t(nc));
    for (uint16_t& v : px) v = uint16_t(rng());
    if (nc == 2 || nc == 4)  // opaque alpha: OpenImageIO's writer would unpremultiply colours
      for (size_t i = size_t(nc) - 1; i < px.size(); i += size_t(nc)) px[i] = 65535;
    const fs::path file = temp("sixteen.png");
    {
      auto out = OIIO::ImageOutput::create(file.string());
      ASSERT_TRUE(out);
      ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(w, h, nc, OIIO::TypeDesc::UINT16)));
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, px.data()));
      out->close();
    }
    const std::vector<unsigned char> bytes = file_bytes(file);
    for (const bool keep16 : {true, false}) EXPECT_EQ(expect_texels_as_oiio(file, bytes, keep16).wide, keep16);
    fs::remove(file);
  }
}

// OpenImageIO writes width x height floats as `file` (its format by the name), 3 channels.
void oiio_write(const fs::path& file, int w, int h, const std::vector<float>& px, OIIO::TypeDesc type,
                const std::vector<std::string>& names = {}, int x0 = 0, int y0 = 0) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  const int nc = names.empty() ? 3 : int(names.size());
  OIIO::ImageSpec spec(w, h, nc, type);
  if (!names.empty()) spec.channelnames = names;
  spec.x = x0;
  spec.y = y0;
  ASSERT_TRUE(out->open(file.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

std::vector<float> oiio_read(const fs::path& file, int* w, int* h, int* nc,
                             std::vector<std::string>* names = nullptr) {
  auto in = OIIO::ImageInput::open(file.string());
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  if (names) *names = in->spec().channelnames;
  *w = in->spec().width;
  *h = in->spec().height;
  *nc = in->spec().nchannels;
  std::vector<float> px(size_t(*w) * size_t(*h) * size_t(*nc));
  EXPECT_TRUE(in->read_image(0, 0, 0, *nc, OIIO::TypeDesc::FLOAT, px.data()));
  return px;
}

std::vector<float> random_radiance(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> px(n);
  for (size_t i = 0; i < n; ++i) {
    // Runs of equal texels (the run-length coder's runs) between noise over 12 stops.
    px[i] = (i / 3) % 17 < 6 ? 0.75f : std::exp2(24.0f * u(rng) - 12.0f);
  }
  return px;
}

// Radiance HDR: a wide image (run-length rows), a narrow one (flat rows, under 8 pixels) and
// one whose rows end early, against OpenImageIO's reader of the same file.
TEST(ImageCodecs, HdrReadsAsOpenImageIOReadsIt) {
  for (const int w : {37, 5}) {
    SCOPED_TRACE(w);
    const int h = 70;  // more than one strip
    const fs::path file = temp("w" + std::to_string(w) + ".hdr");
    oiio_write(file, w, h, random_radiance(size_t(w) * h * 3, uint32_t(w)), OIIO::TypeDesc::FLOAT);
    int ow = 0, oh = 0, nc = 0;
    const std::vector<float> theirs = oiio_read(file, &ow, &oh, &nc);
    const Image mine = read_image(file);
    ASSERT_EQ(int(mine.width), ow);
    ASSERT_EQ(int(mine.height), oh);
    ASSERT_EQ(nc, 3);
    size_t differ = 0;
    for (size_t i = 0; i < theirs.size(); ++i) differ += mine.rgb[i] != theirs[i];
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(read_image_size(file).width, uint32_t(w));

    // Cut in the pixels: refused at the row where the data ends, with nothing read past it.
    std::vector<unsigned char> bytes = file_bytes(file);
    bytes.resize(bytes.size() * 2 / 3);
    Raster r;
    DecodeFailure f;
    EXPECT_FALSE(decode_hdr(bytes.data(), bytes.size(), [](uint64_t, uint64_t) { return std::string(); }, &r, &f));
    EXPECT_GT(f.row, 0);
    EXPECT_LT(f.row, h);
    EXPECT_NE(f.what.find("ends in row"), std::string::npos) << f.what;
    fs::remove(file);
  }
}

// OpenEXR: half and float channels, a data window that starts away from the origin, and
// layers, against OpenImageIO's reader.
TEST(ImageCodecs, ExrReadsAsOpenImageIOReadsIt) {
  const int w = 9, h = 67;
  const std::vector<std::string> names = {"R", "G", "B", "variance.R", "variance.G", "variance.B", "depth.Z"};
  const size_t nc = names.size();
  std::vector<float> px = random_radiance(size_t(w) * h * nc, 3);
  for (const OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT}) {
    SCOPED_TRACE(type.c_str());
    const fs::path file = temp("layers.exr");
    oiio_write(file, w, h, px, type, names, 3, -2);
    int ow = 0, oh = 0, onc = 0;
    std::vector<std::string> order;  // OpenImageIO's channel order
    const std::vector<float> theirs = oiio_read(file, &ow, &oh, &onc, &order);
    ASSERT_EQ(size_t(onc), nc);
    auto at = [&](const std::string& name) {
      return size_t(std::find(order.begin(), order.end(), name) - order.begin());
    };
    const ImageChannels mine = read_image_channels(file);
    ASSERT_EQ(int(mine.image.width), w);
    ASSERT_EQ(int(mine.image.height), h);
    const Image* variance = mine.layer("variance");
    const Image* depth = mine.layer("depth");
    ASSERT_TRUE(variance && depth);
    size_t differ = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (size_t c = 0; c < 3; ++c) {
        const std::string rgb(1, "RGB"[c]);
        differ += mine.image.rgb[i * 3 + c] != theirs[i * nc + at(rgb)];
        differ += variance->rgb[i * 3 + c] != theirs[i * nc + at("variance." + rgb)];
        differ += depth->rgb[i * 3 + c] != theirs[i * nc + at("depth.Z")];
      }
    EXPECT_EQ(differ, 0u);
    fs::remove(file);
  }
}

// What clpt writes, OpenImageIO reads: an EXR's floats, layers and attributes exactly; a PNG's
// bytes and its text chunks; a JPEG close to the image.
TEST(ImageCodecs, WhatClptWritesOpenImageIOReads) {
  Image img(13, 70);
  const std::vector<float> px = random_radiance(img.rgb.size(), 5);
  for (size_t i = 0; i < px.size(); ++i) img.rgb[i] = std::min(px[i], 1.0f);
  NamedChannel variance{kVarianceLayer, img, {"R", "G", "B"}};
  for (float& v : variance.image.rgb) v *= 0.5f;
  ImageMetadata meta;
  meta.strings = {{"Software", "clpt test"}, {"clpt:integrator", "pt"}};
  meta.ints = {{"clpt:spp", 42}};
  meta.floats = {{"clpt:render_seconds", 1.25f}};

  const fs::path exr = temp("out.exr");
  write_image(exr, img, meta, {variance});
  {
    auto in = OIIO::ImageInput::open(exr.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ImageSpec& s = in->spec();
    ASSERT_EQ(s.nchannels, 6);
    EXPECT_EQ(s.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(s.get_int_attribute("clpt:spp"), 42);
    EXPECT_EQ(s.get_float_attribute("clpt:render_seconds"), 1.25f);
    EXPECT_EQ(s.get_string_attribute("clpt:integrator"), "pt");
    EXPECT_EQ(s.get_string_attribute("compression"), "zip");
    std::vector<float> back(size_t(13) * 70 * 6);
    ASSERT_TRUE(in->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, back.data()));
    size_t differ = 0;
    for (size_t i = 0; i < size_t(13) * 70; ++i)
      for (int c = 0; c < 3; ++c) {
        const int at_r = s.channelindex(std::string(1, "RGB"[c]));
        const int at_v = s.channelindex(std::string("variance.") + "RGB"[c]);
        differ += back[i * 6 + size_t(at_r)] != img.rgb[i * 3 + size_t(c)];
        differ += back[i * 6 + size_t(at_v)] != variance.image.rgb[i * 3 + size_t(c)];
      }
    EXPECT_EQ(differ, 0u);
  }
  const ImageChannels mine = read_image_channels(exr);
  EXPECT_EQ(mine.int_attribute("clpt:spp"), 42);
  ASSERT_TRUE(mine.variance());
  EXPECT_EQ(mine.variance()->rgb, variance.image.rgb);
  EXPECT_EQ(mine.image.rgb, img.rgb);
  fs::remove(exr);

  for (const char* ext : {".png", ".jpg"}) {
    SCOPED_TRACE(ext);
    const fs::path file = temp(std::string("out") + ext);
    write_image(file, img, meta);
    auto in = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    ASSERT_EQ(in->spec().width, 13);
    ASSERT_EQ(in->spec().height, 70);
    std::vector<unsigned char> back(size_t(13) * 70 * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data()));
    in->close();
    // The display encoding clpt's reader inverts: read back through clpt, both agree.
    const Image again = read_image(file);
    double worst = 0;
    for (size_t i = 0; i < back.size(); ++i) {
      const float v = back[i] / 255.0f;
      const float lin = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
      worst = std::max(worst, double(std::abs(lin - again.rgb[i])));
    }
    EXPECT_LT(worst, 1e-6) << "clpt and OpenImageIO read different bytes";
    if (std::string(ext) == ".png") {
      auto in2 = OIIO::ImageInput::open(file.string());
      EXPECT_EQ(in2->spec().get_string_attribute("clpt:spp"), "42");
      EXPECT_EQ(in2->spec().get_string_attribute("Software"), "clpt test");
    }
    fs::remove(file);
  }
}

// A grey + alpha PNG read as an image (--env, --reference) is grey: R, G and B all from the
// grey channel, the alpha ignored (OpenImageIO's channel names Y, A once gave G and B the alpha).
TEST(ImageCodecs, GreyAlphaPngReadsAsGrey) {
  const fs::path file = temp("grey-alpha.png");
  const unsigned char px[2 * 2] = {200, 10, 50, 255};  // two pixels: (grey, alpha)
  std::string why;
  ASSERT_TRUE(write_png(file, 2, 1, 2, 8, px, {}, &why)) << why;
  const Image img = read_image(file);
  fs::remove(file);
  ASSERT_EQ(img.width, 2u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(img.rgb[size_t(c)], img.rgb[0]);
    EXPECT_FLOAT_EQ(img.rgb[3 + size_t(c)], img.rgb[3]);
  }
  EXPECT_GT(img.rgb[0], img.rgb[3]) << "grey 200 against 50";
}

// Every prefix of a valid file (every 13th byte) is refused with a reason or decoded; none
// crashes, hangs or allocates past its limits (the sanitizer suite runs this too).
TEST(ImageCodecs, EveryPrefixIsRefusedOrRead) {
  Image img(11, 9);
  const std::vector<float> px = random_radiance(img.rgb.size(), 7);
  for (size_t i = 0; i < px.size(); ++i) img.rgb[i] = std::min(px[i], 1.0f);
  const SizeCheck any = [](uint64_t, uint64_t) { return std::string(); };
  size_t refused = 0, tried = 0;
  for (const char* ext : {".png", ".jpg", ".hdr"}) {
    SCOPED_TRACE(ext);
    const fs::path file = temp(std::string("prefix") + ext);
    if (std::string(ext) == ".hdr") oiio_write(file, 11, 9, img.rgb, OIIO::TypeDesc::FLOAT);
    else write_image(file, img, {});
    const std::vector<unsigned char> bytes = file_bytes(file);
    fs::remove(file);
    for (size_t n = 0; n < bytes.size(); n += 13) {
      Raster r;
      DecodeFailure f;
      const bool ok = std::string(ext) == ".png"   ? decode_png(bytes.data(), n, false, any, &r, &f)
                      : std::string(ext) == ".jpg" ? decode_jpeg(bytes.data(), n, any, &r, &f)
                                                   : decode_hdr(bytes.data(), n, any, &r, &f);
      ++tried;
      if (!ok) {
        ++refused;
        EXPECT_FALSE(f.what.empty());
      }
    }
  }
  EXPECT_GT(refused, tried * 9 / 10) << "a cut-off file should almost never decode";
}

}  // namespace
}  // namespace clpt::image_codecs_test
