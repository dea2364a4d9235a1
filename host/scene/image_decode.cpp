#include "scene/image_decode.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>

namespace clpt {
namespace {

// The format by its signature; nullptr for anything else.
const char* sniff_format(const unsigned char* p, size_t n) {
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (n >= 8 && std::equal(png, png + 8, p)) return "png";
  if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF) return "jpeg";
  return nullptr;
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  if (s.size() > 300) s = s.substr(0, 300) + "...";
  return s;
}

}  // namespace

bool decode_image(const unsigned char* data, size_t size, DecodedImage* out, std::string* why,
                  uint64_t max_dimension, uint64_t max_pixels) {
  const char* format = sniff_format(data, size);
  if (!format) {
    *why = size == 0 ? "the image is empty (0 bytes)" : "not a PNG or JPEG image (unknown signature)";
    return false;
  }
  try {
    OIIO::Filesystem::IOMemReader proxy(data, size);
    // Straight alpha, as glTF means it (OIIO would otherwise premultiply PNG alpha).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(format);
    if (!in) {
      *why = std::string("OpenImageIO has no ") + format + " reader: " + one_line(OIIO::geterror());
      return false;
    }
    const std::string name = std::string("image.") + format;
    OIIO::ImageSpec spec;
    if (!in->open(name, spec, config)) {
      std::string e = one_line(in->geterror());
      *why = std::string("cannot decode the ") + format + " data" + (e.empty() ? "" : ": " + e);
      return false;
    }
    spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels <= 0) {
      *why = "the " + std::string(format) + " header gives a size of " + std::to_string(spec.width) + "x" +
             std::to_string(spec.height);
      return false;
    }
    const uint64_t w = uint64_t(spec.width), h = uint64_t(spec.height);
    if (w > max_dimension || h > max_dimension || w * h > max_pixels) {
      *why = "the image is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than the limit of " +
             std::to_string(max_dimension) + " per side and " + std::to_string(max_pixels) +
             " pixels (--limit image-dimension=N, image-pixels=N)";
      return false;
    }
    const int nc = spec.nchannels;
    const int keep = nc > 4 ? 4 : nc;
    std::vector<unsigned char> pixels(size_t(w * h) * size_t(keep));
    if (!in->read_image(0, 0, 0, keep, OIIO::TypeDesc::UINT8, pixels.data())) {
      std::string e = one_line(in->geterror());
      *why = std::string("cannot decode the ") + format + " pixels" + (e.empty() ? "" : ": " + e);
      return false;
    }
    in->close();
    out->width = uint32_t(w);
    out->height = uint32_t(h);
    out->texels.resize(size_t(w * h));
    for (size_t i = 0; i < out->texels.size(); ++i) {
      const unsigned char* p = &pixels[i * size_t(keep)];
      uint32_t r, g, b, a = 255;
      if (keep <= 2) {
        r = g = b = p[0];
        if (keep == 2) a = p[1];
      } else {
        r = p[0], g = p[1], b = p[2];
        if (keep == 4) a = p[3];
      }
      out->texels[i] = r | g << 8 | b << 16 | a << 24;
    }
    return true;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    *why = std::string("cannot decode the image: ") + e.what();
    return false;
  }
}

DecodedImage placeholder_image() {
  DecodedImage img;
  img.width = img.height = 1;
  img.texels = {0xFFFF00FFu};  // R 255, G 0, B 255, A 255
  return img;
}

}  // namespace clpt
