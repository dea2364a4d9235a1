#include "io/image_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <unistd.h>

#include "io/exr_codec.h"
#include "io/hdr_codec.h"
#include "io/image_bytes.h"
#include "io/jpeg_codec.h"
#include "io/png_codec.h"
#include "io/output_path.h"
#include "util/text.h"
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

float srgb_decode(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

void check_output_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".exr" && ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    throw Error(ExitCode::Usage, "output " + path.string() +
                                     ": unsupported format (use .exr, .png, .jpg or .jpeg)");
  check_writable_path(path, "output");
}

void write_image(const fs::path& path, const Image& image, const ImageMetadata& meta) {
  write_image(path, image, meta, {});
}

ImageLimits film_image_limits(const std::string& raise) {
  ImageLimits limits;
  limits.max_dimension = kMaxFilmSide;
  limits.max_pixels = uint64_t{kMaxFilmSide} * kMaxFilmSide;
  limits.raise = raise;
  return limits;
}

void write_image(const fs::path& path, const Image& image, const ImageMetadata& meta,
                 const std::vector<NamedChannel>& aovs) {
  write_image(path, image, meta, aovs, DisplaySettings{});
}

void write_image(const fs::path& path, const Image& image, const ImageMetadata& meta,
                 const std::vector<NamedChannel>& aovs, const DisplaySettings& display) {
  const std::string ext = lower_extension(path);
  const bool hdr = is_float_format(ext);
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  // Same folder (so rename is atomic).
  const fs::path tmp =
      dir / ("." + path.stem().string() + ".tmp" + std::to_string(::getpid()) + path.extension().string());
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error(ExitCode::Output, "cannot write " + path.string() + ": " + why);
  };

  // Extra layers go into EXR files only; PNG and JPEG have nowhere to put them.
  const std::vector<NamedChannel> no_layers;
  const std::vector<NamedChannel>& layers = hdr ? aovs : no_layers;
  for (size_t l = 0; l < layers.size(); ++l) {
    const NamedChannel& a = layers[l];
    const auto bad = [&](const std::string& why) {
      throw Error(ExitCode::Output, "cannot write " + path.string() + ": layer '" + a.name +
                                        "' " + why);
    };
    if (a.name.empty() || a.name.find('.') != std::string::npos) bad("needs a name without '.'");
    if (a.image.width != image.width || a.image.height != image.height ||
        a.image.rgb.size() != image.rgb.size())
      bad("is " + std::to_string(a.image.width) + "x" + std::to_string(a.image.height) +
          ", the image " + std::to_string(image.width) + "x" + std::to_string(image.height));
    for (size_t k = 0; k < l; ++k)
      if (layers[k].name == a.name) bad("is given twice");
    if (a.channels.size() != 1 && a.channels.size() != 3) bad("needs one or three channels");
  }
  int nch = 3;
  for (const NamedChannel& a : layers) nch += int(a.channels.size());

  std::string why;
  bool ok;
  if (hdr) {
    std::vector<std::string> names = {"R", "G", "B"};
    for (const NamedChannel& a : layers)
      for (const std::string& c : a.channels) names.push_back(a.name + "." + c);
    const size_t px = size_t(image.width) * image.height;
    std::vector<float> interleaved;
    if (!layers.empty()) {  // R G B, then each layer's channels, per pixel
      interleaved.resize(px * size_t(nch));
      for (size_t i = 0; i < px; ++i) {
        float* dst = &interleaved[i * size_t(nch)];
        for (int c = 0; c < 3; ++c) *dst++ = image.rgb[i * 3 + c];
        for (const NamedChannel& l : layers)
          for (size_t c = 0; c < l.channels.size(); ++c) *dst++ = l.image.rgb[i * 3 + c];
      }
    }
    ok = write_exr(tmp, image.width, image.height, names, layers.empty() ? image.rgb.data() : interleaved.data(),
                   meta, &why);
  } else {
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i + 2 < bytes.size(); i += 3) {
      const std::array<float, 3> d = display_encode(display, {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
      for (int c = 0; c < 3; ++c) bytes[i + size_t(c)] = static_cast<unsigned char>(std::lround(d[c] * 255.0f));
    }
    if (ext == ".png") {
      std::vector<std::pair<std::string, std::string>> text = meta.strings;
      for (const auto& [k, v] : meta.ints) text.emplace_back(k, std::to_string(v));
      for (const auto& [k, v] : meta.floats) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.9g", double(v));
        text.emplace_back(k, buf);
      }
      ok = write_png(tmp, image.width, image.height, 3, 8, bytes.data(), text, &why);
    } else {
      ok = write_jpeg(tmp, image.width, image.height, bytes.data(), 95, &why);
    }
  }
  if (!ok) fail(why);
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail(ec.message());
}

namespace {

// Values in one line of an EXR (width x channels) clpt reads at most: OpenEXR sizes a block's
// buffers by them when it opens a file (up to 256 lines a block for DWAB: 256 MiB at 4 bytes).
// 16384 pixels x 16 channels, or 4096 x 64.
constexpr uint64_t kMaxExrLineValues = uint64_t{1} << 18;

// Empty when a width x height image is within `limits`, else the refusal to give.
std::string size_refusal(const ImageLimits& limits, uint64_t w, uint64_t h) {
  return image_size_refusal(w, h, limits.max_dimension, limits.max_pixels, limits.raise);
}

[[noreturn]] void refuse(const fs::path& path, const std::string& why) {
  throw Error(ExitCode::BadInput, path.string() + ": " + why);
}

// An image file past the checks that keep hostile bytes from the decoders: a regular file (a
// FIFO or /dev/zero would block or never end) in one of the formats clpt reads (OpenEXR,
// Radiance HDR, PNG, JPEG, told by their first bytes), PNG and JPEG with their chunks and
// segments checked and ICC profiles dropped (io/image_bytes), an EXR's headers walked and its
// size checked before OpenEXR opens it. PNG, JPEG and HDR files are read into memory.
struct InputImage {
  ImageFormat format = ImageFormat::Unknown;
  std::vector<unsigned char> bytes;  // PNG, JPEG, HDR
};

InputImage open_image(const fs::path& path, const ImageLimits& limits) {
  check_regular_input(path, "");
  auto check_size = [&](uint64_t w, uint64_t h) {
    const std::string why = size_refusal(limits, w, h);
    if (!why.empty()) refuse(path, why);
  };
  std::ifstream file(path, std::ios::binary);
  if (!file) refuse(path, "cannot open the file");
  unsigned char head[16] = {};
  file.read(reinterpret_cast<char*>(head), sizeof head);
  InputImage img;
  img.format = sniff_image(head, size_t(file.gcount()));
  std::error_code size_error;
  const uintmax_t file_size = fs::file_size(path, size_error);
  if (img.format != ImageFormat::Exr && img.format != ImageFormat::Hdr && img.format != ImageFormat::Png &&
      img.format != ImageFormat::Jpeg)
    refuse(path, file.gcount() == 0 ? std::string("the file is empty")
                                    : "not an OpenEXR, Radiance HDR, PNG or JPEG image (unknown signature)");
  if (img.format == ImageFormat::Exr) {
    std::string why;
    ExrExtent extent;
    file.clear();
    if (size_error || !check_exr_headers(file, uint64_t(file_size), &why, &extent))
      refuse(path, size_error ? "cannot read the file's size" : why);
    // OpenEXR sizes its line buffers by the window and the channels when it opens the file.
    check_size(extent.width, extent.height);
    if (extent.width * extent.channels > kMaxExrLineValues)
      refuse(path, "the EXR's lines are " + std::to_string(extent.width) + " pixels of " +
                       std::to_string(extent.channels) + " channels, more than the " +
                       std::to_string(kMaxExrLineValues) + " values a line clpt reads may hold");
    return img;
  }
  if (size_error || file_size > (uintmax_t{1} << 31))
    refuse(path, "cannot read the file (larger than 2 GiB, or its size unknown)");
  std::vector<unsigned char> raw(static_cast<size_t>(file_size));
  file.clear();
  file.seekg(0);
  file.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size()));
  if (size_t(file.gcount()) != raw.size()) refuse(path, "cannot read the file");
  if (img.format == ImageFormat::Hdr) {
    img.bytes = std::move(raw);
    return img;
  }
  std::string why;
  if (img.format == ImageFormat::Png && !check_png_chunks(raw.data(), raw.size(), &why)) refuse(path, why);
  if (!without_icc_profiles(raw.data(), raw.size(), img.format, &img.bytes, &why)) refuse(path, why);
  return img;
}

// A file's pixels as its decoder gives them, with an EXR's channel names and attributes.
struct FileImage {
  Raster raster;
  std::vector<std::string> channels;  // EXR only
  ImageMetadata meta;                 // EXR only
  bool srgb = false;                  // PNG and JPEG: 8- or 16-bit sRGB codes
};

FileImage decode_file(const fs::path& path, const ImageLimits& limits) {
  InputImage in = open_image(path, limits);
  std::string refusal;  // the size check's, passed on as it is
  const SizeCheck check = [&](uint64_t w, uint64_t h) {
    refusal = size_refusal(limits, w, h);
    return refusal;
  };
  FileImage img;
  DecodeFailure f;
  bool ok = false;
  switch (in.format) {
    case ImageFormat::Exr: {
      ExrImage exr;
      ok = read_exr(path, check, &exr, &f);
      img.raster = std::move(exr.raster);
      img.channels = std::move(exr.channels);
      img.meta = std::move(exr.meta);
      break;
    }
    case ImageFormat::Hdr: ok = decode_hdr(in.bytes.data(), in.bytes.size(), check, &img.raster, &f); break;
    case ImageFormat::Png:
      ok = decode_png(in.bytes.data(), in.bytes.size(), true, check, &img.raster, &f);
      img.srgb = true;
      break;
    default:  // JPEG
      ok = decode_jpeg(in.bytes.data(), in.bytes.size(), check, &img.raster, &f);
      img.srgb = true;
      break;
  }
  if (ok) return img;
  if (!refusal.empty()) refuse(path, refusal);
  if (f.row < 0) refuse(path, "cannot read image: " + f.what);
  const uint64_t h = img.raster.height, y = uint64_t(f.row) / kDecodeStripRows * kDecodeStripRows;
  refuse(path, "cannot read scanlines " + std::to_string(y) + ".." +
                   std::to_string(std::min<uint64_t>(h, y + kDecodeStripRows) - 1) + " of " + std::to_string(h) +
                   ": " + f.what);
}

}  // namespace

ImageSize read_image_size(const fs::path& path, const ImageLimits& limits) {
  const InputImage in = open_image(path, limits);
  uint64_t w = 0, h = 0;
  std::string why;
  bool ok;
  if (in.format == ImageFormat::Exr) {
    DecodeFailure f;
    ok = read_exr_size(path, &w, &h, &f);
    why = f.what;
  } else if (in.format == ImageFormat::Hdr) {
    ok = hdr_header_size(in.bytes.data(), in.bytes.size(), &w, &h, &why);
  } else {
    ok = image_header_size(in.bytes.data(), in.bytes.size(), &w, &h);
    if (!ok) why = "the header is cut off";
  }
  if (!ok) refuse(path, "cannot read image: " + why);
  if (w == 0 || h == 0) refuse(path, "empty image (the header gives " + std::to_string(w) + "x" + std::to_string(h) + ")");
  const std::string refusal = size_refusal(limits, w, h);
  if (!refusal.empty()) refuse(path, refusal);
  return {uint32_t(w), uint32_t(h)};
}

Image read_image(const fs::path& path, const ImageLimits& limits) {
  return read_image_channels(path, limits).image;
}

const Image* ImageChannels::layer(const std::string& name) const {
  for (const NamedChannel& l : layers)
    if (l.name == name) return &l.image;
  return nullptr;
}

int ImageChannels::int_attribute(const std::string& name, int fallback) const {
  for (const auto& [k, v] : meta.ints)
    if (k == name) return v;
  return fallback;
}

ImageChannels read_image_channels(const fs::path& path, const ImageLimits& limits) {
  const FileImage file = decode_file(path, limits);
  const Raster& r = file.raster;
  const size_t px = size_t(r.width) * r.height;
  const size_t nch = r.channels;
  const std::vector<std::string>& names = file.channels;

  auto channel_index = [&](const std::string& name) {
    for (size_t c = 0; c < names.size() && c < nch; ++c)
      if (names[c] == name) return int(c);
    return -1;
  };
  auto gather = [&](const std::array<int, 3>& ch, bool srgb) {
    Image img(r.width, r.height);
    for (size_t i = 0; i < px; ++i)
      for (int c = 0; c < 3; ++c) {
        const float v = r.value(i * nch + size_t(ch[c]));
        img.rgb[i * 3 + c] = srgb ? srgb_decode(v) : v;
      }
    return img;
  };

  ImageChannels out;
  std::array<int, 3> rgb = {channel_index("R"), channel_index("G"), channel_index("B")};
  const int luminance = channel_index("Y");
  if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) {
    if (luminance >= 0) rgb = {luminance, luminance, luminance};  // an EXR's Y alone: grey
    else if (nch <= 2) rgb = {0, 0, 0};                            // grey, or grey and alpha
    else rgb = {0, 1, 2};                                          // the first three channels
  }
  out.image = gather(rgb, file.srgb);

  // Layers, in the file's channel order: every prefix L with all of L.R, L.G, L.B, or of
  // L.X, L.Y, L.Z, or with one channel L.c alone (repeated in all three components).
  for (size_t c = 0; c < names.size() && c < nch; ++c) {
    const std::string& n = names[c];
    const size_t dot = n.rfind('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == n.size()) continue;
    const std::string name = n.substr(0, dot), suffix = n.substr(dot + 1);
    if (out.layer(name)) continue;
    bool three = false;
    for (const auto& set : {std::array<const char*, 3>{"R", "G", "B"}, std::array<const char*, 3>{"X", "Y", "Z"}}) {
      if (suffix != set[0]) continue;
      const std::array<int, 3> ch = {int(c), channel_index(name + "." + set[1]), channel_index(name + "." + set[2])};
      if (ch[1] < 0 || ch[2] < 0) continue;
      out.layers.push_back({name, gather(ch, false), {set[0], set[1], set[2]}});
      three = true;
    }
    if (three) continue;
    size_t with_prefix = 0;
    for (const std::string& other : names)
      with_prefix += other.size() > name.size() && other.compare(0, name.size() + 1, name + ".") == 0;
    if (with_prefix == 1) out.layers.push_back({name, gather({int(c), int(c), int(c)}, false), {suffix}});
  }
  out.meta = file.meta;
  return out;
}

}  // namespace clpt
