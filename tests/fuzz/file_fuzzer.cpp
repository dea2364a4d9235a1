// libFuzzer target for the readers other than the glTF loader (issue 23): the image reader
// behind --env, --reference and clpt-diff (clpt::read_image_channels, the io/*_codec decoders underneath),
// the texture decoder (clpt::decode_image and clpt::image_header_size: PNG, JPEG, WebP) and
// the checkpoint reader behind --resume (clpt::read_checkpoint). Built with -DCLPT_FUZZ=ON
// and clang; run through `scripts/fuzz.sh SECONDS file`. See docs/robustness.md.
//
// The first byte of an input picks the reader, the rest is the file:
//   0  read_image_channels of a file named image.hdr     (Radiance RGBE, --env's usual format)
//   1  read_image_channels of a file named image.exr     (OpenEXR)
//   2  read_image_channels of a file named image.png
//   3  read_image_channels of a file named image.jpg
//   4  decode_image of the bytes, with image_header_size (glTF textures)
//   5  read_checkpoint of a file named film.ckpt
// (the byte modulo 6). The contracts: the file readers return or throw clpt::Error with
// BadInput (Usage for a checkpoint of another render), one line naming the file; a returned
// image has width x height pixels within the default ImageLimits; decode_image returns true
// with width x height texels within its limits, or false with a reason, and never throws.
// Anything else (another exception, a crash, a sanitizer report, a leak, a hang, an
// allocation past -malloc_limit_mb) is a finding.
//
// With CLPT_FUZZ_WRITE_SEEDS=DIR in the environment the target writes one small valid input
// per reader into DIR (with the same libraries: OpenImageIO's writers, clpt's checkpoint
// writer) and exits: scripts/fuzz.sh seeds the corpus so.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "io/image_io.h"
#include "render/checkpoint.h"
#include "scene/image_decode.h"
#include "fuzz/harness.h"
#include "util/error.h"
#include "util/log.h"

namespace {

namespace fs = std::filesystem;

constexpr char kSignature[] = "clpt-fuzz-signature";
const char* const kNames[] = {"image.hdr", "image.exr", "image.png", "image.jpg", "", "film.ckpt"};

using clpt::fuzz::write_file;

[[noreturn]] void finding(const char* what) { clpt::fuzz::finding("file_fuzzer", what); }

void check_error(const clpt::Error& e, const fs::path& file, bool usage_allowed) {
  if (e.code() != clpt::ExitCode::BadInput && !(usage_allowed && e.code() == clpt::ExitCode::Usage))
    finding("clpt::Error with an unexpected exit code");
  if (std::strchr(e.what(), '\n')) finding("an error message spans several lines");
  if (!std::strstr(e.what(), file.c_str())) finding("an error message does not name the file");
}

// One small valid input per reader, tagged with its reader's byte.
void write_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path scratch = clpt::fuzz::scratch_dir();
  clpt::Image img(5, 3);
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = float(i % 7) * 0.25f;
  auto tagged = [&](int tag, const fs::path& file, const std::string& name) {
    std::vector<uint8_t> bytes(1, uint8_t(tag));
    FILE* f = std::fopen(file.c_str(), "rb");
    if (!f) std::abort();
    for (int c; (c = std::fgetc(f)) != EOF;) bytes.push_back(uint8_t(c));
    std::fclose(f);
    write_file(dir / name, bytes.data(), bytes.size());
  };
  for (int tag : {0, 1, 2, 3}) {
    const fs::path file = scratch / kNames[tag];
    if (tag == 0) {  // clpt writes no .hdr: OpenImageIO's writer, RLE-coded rows
      auto out = OIIO::ImageOutput::create(file.string());
      OIIO::ImageSpec spec(9, 4, 3, OIIO::TypeDesc::FLOAT);
      std::vector<float> px(9 * 4 * 3, 0.5f);
      if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, px.data()))
        std::abort();
      out->close();
    } else {
      std::vector<clpt::NamedChannel> layers;
      if (tag == 1) layers.push_back({clpt::kVarianceLayer, img});
      clpt::write_image(file, img, {}, layers);
    }
    tagged(tag, file, std::string("seed-") + kNames[tag]);
  }
  // Textures: the PNG and JPEG above, and a WebP.
  for (int tag : {2, 3}) {
    std::vector<uint8_t> bytes(1, 4);
    FILE* f = std::fopen((scratch / kNames[tag]).c_str(), "rb");
    for (int c; (c = std::fgetc(f)) != EOF;) bytes.push_back(uint8_t(c));
    std::fclose(f);
    write_file(dir / (std::string("seed-texture-") + kNames[tag]), bytes.data(), bytes.size());
  }
  {
    const fs::path file = scratch / "image.webp";
    auto out = OIIO::ImageOutput::create(file.string());
    OIIO::ImageSpec spec(5, 3, 4, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> px(5 * 3 * 4, 200);
    if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()))
      std::abort();
    out->close();
    tagged(4, file, "seed-texture-image.webp");
  }
  {
    clpt::FilmState s;
    s.width = 3, s.height = 2, s.samples_per_pixel = 4;
    s.sum.assign(3 * 2 * 4, 1.0f);
    s.sum_sq.assign(3 * 2 * 4, 2.0f);
    s.ray_counts.assign(3 * 2, 7);
    const fs::path file = scratch / kNames[5];
    clpt::write_checkpoint(file, kSignature, s);
    tagged(5, file, "seed-film.ckpt");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  clpt::log::set_level(clpt::log::Level::Quiet);
  OIIO::attribute("threads", 1);  // one input at a time; OpenImageIO's pool would only add noise
  clpt::fuzz::make_scratch_dir("file-fuzz");
  if (const char* seeds = std::getenv("CLPT_FUZZ_WRITE_SEEDS")) {
    write_seeds(seeds);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int reader = data[0] % 6;
  const uint8_t* body = data + 1;
  const size_t body_size = size - 1;

  if (reader == 4) {
    uint64_t hw = 0, hh = 0;
    const bool header = clpt::image_header_size(body, body_size, &hw, &hh);
    (void)header;
    clpt::DecodedImage img;
    std::string why;
    bool ok = false;
    try {
      ok = clpt::decode_image(body, body_size, &img, &why);
    } catch (...) {
      finding("decode_image threw");
    }
    if (ok) {
      if (img.width == 0 || img.height == 0) finding("decode_image returned an empty image");
      if (img.width > clpt::kMaxImageDimension || img.height > clpt::kMaxImageDimension ||
          uint64_t(img.width) * img.height > clpt::kMaxImagePixels)
        finding("decode_image returned an image past its limits");
      if (img.texels.size() != size_t(img.width) * img.height) finding("texel count differs from the size");
    } else if (why.empty()) {
      finding("decode_image refused without a reason");
    }
    return 0;
  }

  const fs::path file = clpt::fuzz::scratch_dir() / kNames[reader];
  write_file(file, body, body_size);
  if (reader == 5) {
    try {
      const clpt::FilmState s = clpt::read_checkpoint(file, kSignature);
      const size_t px = size_t(s.width) * s.height;
      if (s.sum.size() != px * 4 || s.sum_sq.size() != px * 4 || s.ray_counts.size() != px)
        finding("a checkpoint's arrays differ from its size");
    } catch (const clpt::Error& e) {
      check_error(e, file, true);
    }
    return 0;
  }
  try {
    const clpt::ImageChannels ch = clpt::read_image_channels(file);
    const clpt::ImageLimits limits;
    const clpt::Image& im = ch.image;
    if (im.width == 0 || im.height == 0 || im.width > limits.max_dimension || im.height > limits.max_dimension ||
        uint64_t(im.width) * im.height > limits.max_pixels)
      finding("read_image_channels returned an image past its limits");
    if (im.rgb.size() != size_t(im.width) * im.height * 3) finding("pixel count differs from the size");
    for (const clpt::NamedChannel& l : ch.layers)
      if (l.image.rgb.size() != im.rgb.size()) finding("a layer differs in size from the image");
  } catch (const clpt::Error& e) {
    check_error(e, file, false);
  }
  return 0;
}
