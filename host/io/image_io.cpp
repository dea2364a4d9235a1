#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <unistd.h>

#include "util/error.h"

namespace clpt {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool is_float_format(const std::string& ext) { return ext == ".exr"; }

float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;  // also maps NaN to 0
  if (linear >= 1.0f) return 1.0f;
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

void check_output_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".exr" && ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    throw Error(ExitCode::Usage, "output " + path.string() +
                                     ": unsupported format (use .exr, .png, .jpg or .jpeg)");
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(ExitCode::Output, "output " + path.string() + ": folder " + dir.string() +
                                      " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error(ExitCode::Output, "output " + path.string() + ": folder " + dir.string() +
                                      " is not writable");
  if (fs::is_directory(path, ec))
    throw Error(ExitCode::Output, "output " + path.string() + " is a folder");
}

void write_image(const fs::path& path, const Image& image, const ImageMetadata& meta) {
  const std::string ext = lower_extension(path);
  const bool hdr = is_float_format(ext);
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  // Same folder (so rename is atomic), same extension (so OIIO picks the format).
  const fs::path tmp =
      dir / ("." + path.stem().string() + ".tmp" + std::to_string(::getpid()) + path.extension().string());
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error(ExitCode::Output, "cannot write " + path.string() + ": " + why);
  };

  auto out = OIIO::ImageOutput::create(tmp.string());
  if (!out) fail("no image writer for '" + ext + "' (" + OIIO::geterror() + ")");
  OIIO::ImageSpec spec(int(image.width), int(image.height), 3,
                       hdr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (hdr) spec.attribute("compression", "zip");
  else spec.attribute("oiio:ColorSpace", "sRGB");
  if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:95");
  for (const auto& [k, v] : meta.strings) spec.attribute(k, v);
  for (const auto& [k, v] : meta.ints) spec.attribute(k, v);
  for (const auto& [k, v] : meta.floats) spec.attribute(k, v);

  if (!out->open(tmp.string(), spec)) fail(out->geterror());
  bool ok;
  if (hdr) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
  } else {
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i)
      bytes[i] = static_cast<unsigned char>(std::lround(srgb_encode(image.rgb[i]) * 255.0f));
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!ok) {
    const std::string err = out->geterror();
    out->close();
    fail(err);
  }
  if (!out->close()) fail(out->geterror());
  out.reset();
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail(ec.message());
}

Image read_image(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw Error(ExitCode::BadInput, path.string() + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error(ExitCode::BadInput, path.string() + ": empty image");
  std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
    throw Error(ExitCode::BadInput, path.string() + ": " + in->geterror());
  const bool decode = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                      spec.format.basetype == OIIO::TypeDesc::UINT16;
  Image img(uint32_t(spec.width), uint32_t(spec.height));
  for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = pixels[i * spec.nchannels + std::min(c, spec.nchannels - 1)];
      img.rgb[i * 3 + c] = decode ? srgb_decode(v) : v;
    }
  return img;
}

}  // namespace clpt
