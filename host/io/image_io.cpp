#include "io/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <memory>
#include <unistd.h>

#include "io/image_bytes.h"
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
  // Same folder (so rename is atomic), same extension (so OIIO picks the format).
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

  auto out = OIIO::ImageOutput::create(tmp.string());
  if (!out) fail("no image writer for '" + ext + "' (" + OIIO::geterror() + ")");
  OIIO::ImageSpec spec(int(image.width), int(image.height), nch,
                       hdr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!layers.empty()) {
    spec.channelnames = {"R", "G", "B"};
    for (const NamedChannel& a : layers)
      for (const std::string& c : a.channels) spec.channelnames.push_back(a.name + "." + c);
  }
  if (hdr) spec.attribute("compression", "zip");
  else spec.attribute("oiio:ColorSpace", "sRGB");
  if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:95");
  for (const auto& [k, v] : meta.strings) spec.attribute(k, v);
  for (const auto& [k, v] : meta.ints) spec.attribute(k, v);
  for (const auto& [k, v] : meta.floats) spec.attribute(k, v);

  if (!out->open(tmp.string(), spec)) fail(out->geterror());
  bool ok;
  if (hdr && layers.empty()) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
  } else if (hdr) {
    // Interleave: R G B, then each layer's channels, per pixel.
    const size_t px = size_t(image.width) * image.height;
    std::vector<float> buf(px * size_t(nch));
    for (size_t i = 0; i < px; ++i) {
      float* dst = &buf[i * size_t(nch)];
      for (int c = 0; c < 3; ++c) *dst++ = image.rgb[i * 3 + c];
      for (const NamedChannel& l : layers)
        for (size_t c = 0; c < l.channels.size(); ++c) *dst++ = l.image.rgb[i * 3 + c];
    }
    ok = out->write_image(OIIO::TypeDesc::FLOAT, buf.data());
  } else {
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i + 2 < bytes.size(); i += 3) {
      const std::array<float, 3> d = display_encode(display, {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
      for (int c = 0; c < 3; ++c) bytes[i + size_t(c)] = static_cast<unsigned char>(std::lround(d[c] * 255.0f));
    }
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

namespace {

// Values in one line of an EXR (width x channels) clpt reads at most: OpenEXR sizes a block's
// buffers by them when it opens a file (up to 256 lines a block for DWAB: 256 MiB at 4 bytes).
// 16384 pixels x 16 channels, or 4096 x 64.
constexpr uint64_t kMaxExrLineValues = uint64_t{1} << 18;

// An image open for reading, with what its reader reads from (destroyed after the reader).
struct OpenImage {
  std::vector<unsigned char> bytes;                         // PNG and JPEG: the cleaned file
  std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;     // ... and the reader's view of it
  std::unique_ptr<OIIO::ImageInput> in;
};

// Opens an image for reading: a regular file (a FIFO or /dev/zero would block or never end)
// in one of the formats clpt reads (OpenEXR, Radiance HDR, PNG, JPEG, told by their first
// bytes, each with its own reader rather than whichever OpenImageIO guesses), with a
// non-empty size within the limits. PNG and JPEG are read into memory and pass the texture
// decoder's checks first (io/image_bytes: PNG chunks and CRCs, no ICC profiles).
OpenImage open_image(const fs::path& path, const ImageLimits& limits) {
  check_regular_input(path, "");
  auto fail = [&](const std::string& why) { throw Error(ExitCode::BadInput, path.string() + ": " + why); };
  auto check_size = [&](uint64_t w, uint64_t h) {
    const std::string why = image_size_refusal(w, h, limits.max_dimension, limits.max_pixels, limits.raise);
    if (!why.empty()) fail(why);
  };
  std::ifstream file(path, std::ios::binary);
  if (!file) fail("cannot open the file");
  unsigned char head[16] = {};
  file.read(reinterpret_cast<char*>(head), sizeof head);
  const ImageFormat format = sniff_image(head, size_t(file.gcount()));
  std::error_code size_error;
  const uintmax_t file_size = fs::file_size(path, size_error);
  if (format != ImageFormat::Exr && format != ImageFormat::Hdr && format != ImageFormat::Png &&
      format != ImageFormat::Jpeg)
    fail(file.gcount() == 0 ? std::string("the file is empty")
                            : "not an OpenEXR, Radiance HDR, PNG or JPEG image (unknown signature)");
  if (format == ImageFormat::Exr) {
    std::string why;
    ExrExtent extent;
    file.clear();
    if (size_error || !check_exr_headers(file, uint64_t(file_size), &why, &extent))
      fail(size_error ? "cannot read the file's size" : why);
    // OpenEXR sizes its line buffers by the window and the channels when it opens the file.
    check_size(extent.width, extent.height);
    if (extent.width * extent.channels > kMaxExrLineValues)
      fail("the EXR's lines are " + std::to_string(extent.width) + " pixels of " + std::to_string(extent.channels) +
           " channels, more than the " + std::to_string(kMaxExrLineValues) + " values a line clpt reads may hold");
  }
  OpenImage img;
  std::string name = path.string();
  OIIO::ImageSpec config;
  if (format == ImageFormat::Png || format == ImageFormat::Jpeg) {
    if (size_error || file_size > (uintmax_t{1} << 31))
      fail("cannot read the file (larger than 2 GiB, or its size unknown)");
    std::vector<unsigned char> raw(static_cast<size_t>(file_size));
    file.seekg(0);
    file.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size()));
    if (size_t(file.gcount()) != raw.size()) fail("cannot read the file");
    std::string why;
    if (format == ImageFormat::Png && !check_png_chunks(raw.data(), raw.size(), &why)) fail(why);
    if (!without_icc_profiles(raw.data(), raw.size(), format, &img.bytes, &why)) fail(why);
    img.proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(img.bytes.data(), img.bytes.size());
    OIIO::Filesystem::IOProxy* proxy = img.proxy.get();
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    name = std::string("image.") + oiio_format_name(format);
  }
  file.close();
  img.in = OIIO::ImageInput::create(oiio_format_name(format));
  OIIO::ImageSpec spec;
  if (!img.in) fail(std::string("OpenImageIO has no ") + oiio_format_name(format) + " reader: " + one_line(OIIO::geterror()));
  if (!img.in->open(name, spec, config)) fail("cannot read image: " + one_line(img.in->geterror()));
  const OIIO::ImageSpec& s = img.in->spec();
  if (s.width <= 0 || s.height <= 0 || s.nchannels <= 0 || s.depth > 1)
    fail("empty image (the header gives " + std::to_string(s.width) + "x" + std::to_string(s.height) + ")");
  check_size(uint64_t(s.width), uint64_t(s.height));
  return img;
}

// The pixels, nch floats each, read in strips of scanlines. Memory grows strip by strip with
// what was really decoded (a vector's growth: at most twice that), never to the header's
// claim at once: a file that lies about its size fails at its first missing strip.
std::vector<float> read_pixels(OIIO::ImageInput& in, const fs::path& path) {
  const OIIO::ImageSpec& spec = in.spec();
  const size_t row = size_t(spec.width) * size_t(spec.nchannels);
  const int strip = 64;
  std::vector<float> pixels;
  for (int y = 0; y < spec.height; y += strip) {
    const int y_end = std::min(spec.height, y + strip);
    pixels.resize(size_t(y_end) * row);
    // A reader that reports a problem and still returns pixels (libjpeg pads a JPEG whose data
    // ends early with grey, and warns once per missing row) is damaged input too.
    if (!in.read_scanlines(0, 0, spec.y + y, spec.y + y_end, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                           pixels.data() + size_t(y) * row) ||
        in.has_error()) {
      const std::string e = one_line(in.geterror());
      throw Error(ExitCode::BadInput, path.string() + ": cannot read scanlines " + std::to_string(y) + ".." +
                                          std::to_string(y_end - 1) + " of " + std::to_string(spec.height) +
                                          (e.empty() ? std::string() : ": " + e));
    }
  }
  return pixels;
}

}  // namespace

ImageSize read_image_size(const fs::path& path, const ImageLimits& limits) {
  const OpenImage img = open_image(path, limits);
  return {uint32_t(img.in->spec().width), uint32_t(img.in->spec().height)};
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
  OpenImage img = open_image(path, limits);
  OIIO::ImageInput* in = img.in.get();
  const OIIO::ImageSpec& spec = in->spec();
  const size_t px = size_t(spec.width) * size_t(spec.height);
  const size_t nch = size_t(spec.nchannels);
  const std::vector<float> pixels = read_pixels(*in, path);
  const bool decode = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                      spec.format.basetype == OIIO::TypeDesc::UINT16;

  auto channel_index = [&](const std::string& name) {
    for (size_t c = 0; c < spec.channelnames.size() && c < nch; ++c)
      if (spec.channelnames[c] == name) return int(c);
    return -1;
  };
  auto gather = [&](const std::array<int, 3>& ch, bool srgb) {
    Image img(uint32_t(spec.width), uint32_t(spec.height));
    for (size_t i = 0; i < px; ++i)
      for (int c = 0; c < 3; ++c) {
        const float v = pixels[i * nch + size_t(ch[c])];
        img.rgb[i * 3 + c] = srgb ? srgb_decode(v) : v;
      }
    return img;
  };

  ImageChannels out;
  std::array<int, 3> rgb = {channel_index("R"), channel_index("G"), channel_index("B")};
  if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0)  // unnamed channels: the first three, or grey
    for (int c = 0; c < 3; ++c) rgb[c] = std::min(c, spec.nchannels - 1);
  out.image = gather(rgb, decode);

  // Layers, in the file's channel order: every prefix L with all of L.R, L.G, L.B, or of
  // L.X, L.Y, L.Z, or with one channel L.c alone (repeated in all three components).
  for (size_t c = 0; c < spec.channelnames.size() && c < nch; ++c) {
    const std::string& n = spec.channelnames[c];
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
    for (const std::string& other : spec.channelnames)
      with_prefix += other.size() > name.size() && other.compare(0, name.size() + 1, name + ".") == 0;
    if (with_prefix == 1) out.layers.push_back({name, gather({int(c), int(c), int(c)}, false), {suffix}});
  }

  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const OIIO::TypeDesc t = p.type();
    if (p.nvalues() != 1) continue;
    if (t == OIIO::TypeDesc::INT) out.meta.ints.emplace_back(p.name().string(), p.get_int());
    else if (t == OIIO::TypeDesc::FLOAT)
      out.meta.floats.emplace_back(p.name().string(), p.get_float());
    else if (t == OIIO::TypeDesc::STRING)
      out.meta.strings.emplace_back(p.name().string(), p.get_string());
  }
  return out;
}

}  // namespace clpt
