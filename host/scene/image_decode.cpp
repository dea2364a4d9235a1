#include "scene/image_decode.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <memory>

namespace clpt {
namespace {

// The format by its signature; nullptr for anything else.
const char* sniff_format(const unsigned char* p, size_t n) {
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (n >= 8 && std::equal(png, png + 8, p)) return "png";
  if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF) return "jpeg";
  if (n >= 12 && std::equal(p, p + 4, "RIFF") && std::equal(p + 8, p + 12, "WEBP")) return "webp";
  return nullptr;
}

bool is_ktx2(const unsigned char* p, size_t n) {
  static const unsigned char ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  return n >= 12 && std::equal(ktx2, ktx2 + 12, p);
}

uint32_t read_u32le(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

uint32_t read_u32be(const unsigned char* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

// CRC-32 of PNG chunks (ISO 3309, as zlib's crc32), table-driven.
uint32_t png_crc(const unsigned char* p, size_t n) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// The chunk structure of a PNG (after its signature): every chunk within the data, with a
// correct CRC, IHDR first, IEND present. OpenImageIO 2.4 lets libpng longjmp out of its
// read callback on a truncated file, skipping destructors (the fuzzer found the leak), and
// libpng prints its own messages: so truncated and damaged files are refused here first.
bool check_png_chunks(const unsigned char* p, size_t n, std::string* why) {
  size_t at = 8;
  for (int index = 0;; ++index) {
    if (n - at < 12) {
      *why = "truncated PNG: chunk " + std::to_string(index) + " at byte " + std::to_string(at) +
             " is cut off (no IEND chunk)";
      return false;
    }
    const uint32_t length = read_u32be(p + at);
    const std::string type(reinterpret_cast<const char*>(p + at + 4), 4);
    if (length > 0x7FFFFFFFu || length > n - at - 12) {
      *why = "truncated PNG: chunk " + std::to_string(index) + " at byte " + std::to_string(at) +
             " claims " + std::to_string(length) + " bytes, past the end of the data";
      return false;
    }
    if (png_crc(p + at + 4, size_t(length) + 4) != read_u32be(p + at + 8 + length)) {
      *why = "damaged PNG: chunk " + std::to_string(index) + " at byte " + std::to_string(at) +
             " has a wrong CRC";
      return false;
    }
    if (index == 0 && type != "IHDR") {
      *why = "damaged PNG: the first chunk is not IHDR";
      return false;
    }
    at += size_t(length) + 12;
    if (type == "IEND") return true;
  }
}

// Whether a JPEG's frame is Huffman coded (SOF0 to SOF3, SOF5 to SOF7): the markers are
// walked from SOI to the first SOF. Arithmetic-coded frames (SOF9 to SOF15) answer false.
bool jpeg_is_huffman(const unsigned char* p, size_t size) {
  size_t at = 2;  // after SOI
  while (at + 4 <= size) {
    if (p[at] != 0xFF) return false;
    const unsigned char m = p[at + 1];
    if (m == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC) return m < 0xC8;
    const size_t length = size_t(p[at + 2]) << 8 | p[at + 3];
    if (length < 2) return false;
    at += 2 + length;
  }
  return false;
}

uint32_t read_u24le(const unsigned char* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16; }

// The first SOF segment's height and width (the frame header: length, precision, Y, X).
bool jpeg_frame_size(const unsigned char* p, size_t size, uint64_t* w, uint64_t* h) {
  size_t at = 2;  // after SOI
  while (at + 4 <= size) {
    if (p[at] != 0xFF) return false;
    const unsigned char m = p[at + 1];
    if (m == 0xFF) {
      ++at;
      continue;
    }
    if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC) {
      if (at + 9 > size) return false;
      *h = uint64_t(p[at + 5]) << 8 | p[at + 6];
      *w = uint64_t(p[at + 7]) << 8 | p[at + 8];
      return true;
    }
    const size_t length = size_t(p[at + 2]) << 8 | p[at + 3];
    if (length < 2) return false;
    at += 2 + length;
  }
  return false;
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
    *why = size == 0        ? "the image is empty (0 bytes)"
           : is_ktx2(data, size) ? "a KTX2 (Basis Universal) image, which clpt cannot decode (Debian packages no "
                                   "KTX2 transcoder; give the texture a PNG or JPEG source)"
                             : "not a PNG, JPEG or WebP image (unknown signature)";
    return false;
  }
  if (std::string(format) == "png" && !check_png_chunks(data, size, why)) return false;
  // WebP: a RIFF container whose size field covers the file (libwebp reads past a short one).
  if (std::string(format) == "webp" && uint64_t(read_u32le(data + 4)) + 8 > size) {
    *why = "truncated WebP: the RIFF header gives " + std::to_string(uint64_t(read_u32le(data + 4)) + 8) +
           " bytes, the data has " + std::to_string(size);
    return false;
  }
  auto too_large = [&](uint64_t w, uint64_t h) {
    if (w <= max_dimension && h <= max_dimension && w * h <= max_pixels) return false;
    *why = "the image is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than the limit of " +
           std::to_string(max_dimension) + " per side and " + std::to_string(max_pixels) +
           " pixels (--limit image-dimension=N, image-pixels=N)";
    return true;
  };
  // The size from the header first: a decoder may allocate the whole image when it opens it.
  uint64_t header_w = 0, header_h = 0;
  if (image_header_size(data, size, &header_w, &header_h) && too_large(header_w, header_h)) return false;
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
    if (too_large(w, h)) return false;
    // A JPEG whose header claims more pixels than its bytes can code: Huffman coding spends
    // at least 2 bits on every 8 x 8 block of the first component (a 1-bit DC code and a
    // 1-bit end of block), w h / 256 bytes; with a margin of 4, fewer than w h / 1024 bytes
    // is a lying header. libjpeg pads such an image with grey and OIIO reports success
    // (issue 23, class 7: an 8x8 JPEG claiming 16384x4096 rendered, 977 MB, exit 0).
    if (std::string(format) == "jpeg" && jpeg_is_huffman(data, size) && uint64_t(size) * 1024 < w * h) {
      *why = "the JPEG header gives a size of " + std::to_string(w) + "x" + std::to_string(h) +
             ", more than its " + std::to_string(size) + " bytes can hold (a damaged or lying header)";
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

bool image_header_size(const unsigned char* p, size_t size, uint64_t* w, uint64_t* h) {
  const char* format = sniff_format(p, size);
  if (!format) return false;
  const std::string f(format);
  if (f == "png") {  // signature, then IHDR: length, type, width, height (big-endian)
    if (size < 24 || !std::equal(p + 12, p + 16, "IHDR")) return false;
    *w = read_u32be(p + 16);
    *h = read_u32be(p + 20);
    return true;
  }
  if (f == "jpeg") return jpeg_frame_size(p, size, w, h);
  // WebP: RIFF, size, WEBP, then the first chunk (its FourCC and size) at byte 12.
  if (size < 30) return false;
  if (std::equal(p + 12, p + 16, "VP8X")) {  // flags, then canvas width - 1, height - 1 (24 bits)
    *w = uint64_t(read_u24le(p + 24)) + 1;
    *h = uint64_t(read_u24le(p + 27)) + 1;
    return true;
  }
  if (std::equal(p + 12, p + 16, "VP8L")) {  // signature 0x2F, then 14 bits each of w - 1, h - 1
    if (p[20] != 0x2F) return false;
    const uint32_t bits = read_u32le(p + 21);
    *w = uint64_t(bits & 0x3FFFu) + 1;
    *h = uint64_t((bits >> 14) & 0x3FFFu) + 1;
    return true;
  }
  if (std::equal(p + 12, p + 16, "VP8 ")) {  // frame tag (3), start code 9D 01 2A, 14-bit w, h
    if (p[23] != 0x9D || p[24] != 0x01 || p[25] != 0x2A) return false;
    *w = (uint64_t(p[26]) | uint64_t(p[27]) << 8) & 0x3FFFu;
    *h = (uint64_t(p[28]) | uint64_t(p[29]) << 8) & 0x3FFFu;
    return true;
  }
  return false;
}

DecodedImage placeholder_image() {
  DecodedImage img;
  img.width = img.height = 1;
  img.texels = {0xFFFF00FFu};  // R 255, G 0, B 255, A 255
  return img;
}

}  // namespace clpt
