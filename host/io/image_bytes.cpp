#include "io/image_bytes.h"

#include <algorithm>
#include <array>

namespace clpt {
namespace {

uint32_t le32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

uint32_t be32(const unsigned char* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

uint32_t le24(const unsigned char* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16; }

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

}  // namespace

ImageFormat sniff_image(const unsigned char* p, size_t n) {
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  static const unsigned char ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  static const unsigned char exr[4] = {0x76, 0x2F, 0x31, 0x01};
  if (n >= 8 && std::equal(png, png + 8, p)) return ImageFormat::Png;
  if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF) return ImageFormat::Jpeg;
  if (n >= 12 && std::equal(p, p + 4, "RIFF") && std::equal(p + 8, p + 12, "WEBP")) return ImageFormat::Webp;
  if (n >= 12 && std::equal(ktx2, ktx2 + 12, p)) return ImageFormat::Ktx2;
  if (n >= 4 && std::equal(exr, exr + 4, p)) return ImageFormat::Exr;
  if (n >= 2 && p[0] == '#' && p[1] == '?') return ImageFormat::Hdr;  // #?RADIANCE, #?RGBE
  return ImageFormat::Unknown;
}

const char* image_format_name(ImageFormat format) {
  switch (format) {
    case ImageFormat::Png: return "png";
    case ImageFormat::Jpeg: return "jpeg";
    case ImageFormat::Webp: return "webp";
    case ImageFormat::Exr: return "openexr";
    case ImageFormat::Hdr: return "hdr";
    default: return nullptr;
  }
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
    const uint32_t length = be32(p + at);
    const std::string type(reinterpret_cast<const char*>(p + at + 4), 4);
    if (length > 0x7FFFFFFFu || length > n - at - 12) {
      *why = "truncated PNG: chunk " + std::to_string(index) + " at byte " + std::to_string(at) +
             " claims " + std::to_string(length) + " bytes, past the end of the data";
      return false;
    }
    if (png_crc(p + at + 4, size_t(length) + 4) != be32(p + at + 8 + length)) {
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

bool image_header_size(const unsigned char* p, size_t size, uint64_t* w, uint64_t* h) {
  const ImageFormat f = sniff_image(p, size);
  if (f == ImageFormat::Png) {  // signature, then IHDR: length, type, width, height (big-endian)
    if (size < 24 || !std::equal(p + 12, p + 16, "IHDR")) return false;
    *w = be32(p + 16);
    *h = be32(p + 20);
    return true;
  }
  if (f == ImageFormat::Jpeg) return jpeg_frame_size(p, size, w, h);
  if (f != ImageFormat::Webp) return false;
  // WebP: RIFF, size, WEBP, then the first chunk (its FourCC and size) at byte 12.
  if (size < 30) return false;
  if (std::equal(p + 12, p + 16, "VP8X")) {  // flags, then canvas width - 1, height - 1 (24 bits)
    *w = uint64_t(le24(p + 24)) + 1;
    *h = uint64_t(le24(p + 27)) + 1;
    return true;
  }
  if (std::equal(p + 12, p + 16, "VP8L")) {  // signature 0x2F, then 14 bits each of w - 1, h - 1
    if (p[20] != 0x2F) return false;
    const uint32_t bits = le32(p + 21);
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

// Whether an EXR attribute's value is exactly `value.size()` bytes of its type, as OpenEXR
// 3.1 reads it: OpenEXR reads known types by their own layout, not by the declared size, so a
// value of another size puts the rest of the header out of step with this walk.
static bool exr_value_fits(const std::string& type, const std::vector<unsigned char>& v) {
  static const std::pair<const char*, size_t> fixed[] = {
      {"box2i", 16}, {"box2f", 16},  {"compression", 1}, {"lineOrder", 1}, {"envmap", 1},
      {"deepImageState", 1}, {"float", 4}, {"double", 8}, {"int", 4}, {"v2i", 8},
      {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24},
      {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"chromaticities", 32},
      {"keycode", 28}, {"timecode", 8}, {"rational", 8}, {"tiledesc", 9}};
  for (const auto& [name, bytes] : fixed)
    if (type == name) return v.size() == bytes;
  const size_t n = v.size();
  if (type == "floatvector") return n % 4 == 0;
  if (type == "stringvector") {  // (int32 length, bytes) until the value ends
    for (size_t at = 0; at < n;) {
      if (n - at < 4) return false;
      const uint32_t len = le32(v.data() + at);
      if (len > n - at - 4) return false;
      at += 4 + len;
    }
    return true;
  }
  if (type == "preview") {  // width, height, then RGBA8 pixels
    if (n < 8) return false;
    const uint64_t w = le32(v.data()), h = le32(v.data() + 4);
    return w * h * 4 == n - 8;
  }
  if (type == "chlist") {  // (name, 0, 16 bytes) per channel, then a 0
    size_t at = 0;
    for (;;) {
      if (at >= n) return false;
      if (v[at] == 0) return at + 1 == n;
      while (at < n && v[at] != 0) ++at;
      if (n - at < 17) return false;
      at += 17;
    }
  }
  return true;  // string, opaque and other types: read as `size` bytes
}

// Bytes from a file, fit for a one-line message: anything but printable ASCII becomes '?'.
static std::string printable_text(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (c < 0x20 || c > 0x7E) c = '?';
  return out;
}

bool check_exr_headers(std::istream& in, uint64_t file_size, std::string* why, ExrExtent* largest) {
  *largest = ExrExtent{};
  unsigned char head[8];
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(head), 8)) {
    *why = "truncated EXR: no version field";
    return false;
  }
  const uint32_t version = le32(head + 4);
  const bool multipart = version & 0x1000u, long_names = version & 0x400u;
  const size_t max_name = long_names ? 255 : 31;
  uint64_t at = 8;
  // A zero-terminated name or type; false at the end of the file or past max_name.
  auto read_text = [&](std::string* text) {
    text->clear();
    for (;;) {
      const int c = in.get();
      if (c == EOF) return false;
      ++at;
      if (c == 0) return true;
      if (text->size() == max_name) return false;
      text->push_back(char(c));
    }
  };
  for (int part = 0;; ++part) {
    std::string name, type;
    for (int attribute = 0;; ++attribute) {
      if (!read_text(&name)) {
        *why = "damaged EXR: header " + std::to_string(part) + " attribute " + std::to_string(attribute) +
               " has no name of at most " + std::to_string(max_name) + " characters before the end of the file";
        return false;
      }
      if (name.empty()) break;  // the end of this header
      unsigned char size_bytes[4];
      if (!read_text(&type) || !in.read(reinterpret_cast<char*>(size_bytes), 4)) {
        *why = "truncated EXR: attribute '" + printable_text(name) + "' is cut off";
        return false;
      }
      at += 4;
      const uint32_t size = le32(size_bytes);
      if (size > 0x7FFFFFFFu || size > file_size - std::min(file_size, at)) {
        *why = "damaged EXR: attribute '" + printable_text(name) + "' (" + printable_text(type) + ") claims " +
               std::to_string(size) +
               " bytes, past the end of the file";
        return false;
      }
      std::vector<unsigned char> value(size);
      if (size && !in.read(reinterpret_cast<char*>(value.data()), std::streamsize(size))) {
        *why = "truncated EXR: attribute '" + printable_text(name) + "' is cut off";
        return false;
      }
      at += size;
      if (!exr_value_fits(type, value)) {
        *why = "damaged EXR: attribute '" + printable_text(name) + "' (" + printable_text(type) + ") of " +
               std::to_string(size) + " bytes does not hold a value of its type";
        return false;
      }
      if (name == "dataWindow" && type == "box2i") {
        int32_t box[4];
        for (int k = 0; k < 4; ++k) box[k] = int32_t(le32(value.data() + 4 * k));
        const int64_t w = int64_t(box[2]) - box[0] + 1, h = int64_t(box[3]) - box[1] + 1;
        if (w <= 0 || h <= 0) {
          *why = "damaged EXR: an empty data window (" + std::to_string(w) + "x" + std::to_string(h) + ")";
          return false;
        }
        largest->width = std::max(largest->width, uint64_t(w));
        largest->height = std::max(largest->height, uint64_t(h));
      }
      if (name == "channels" && type == "chlist") {
        uint64_t n = 0;
        for (size_t k = 0; k < value.size() && value[k] != 0; ++n) {
          while (value[k] != 0) ++k;
          k += 17;
        }
        largest->channels = std::max(largest->channels, n);
      }
    }
    // One header, or (multi-part) headers until an empty one: a zero byte right after the
    // previous header's end.
    if (!multipart) break;
    const int next = in.peek();
    if (next == EOF) {
      *why = "truncated EXR: the multi-part headers do not end";
      return false;
    }
    if (next == 0) break;
  }
  return true;
}

bool without_icc_profiles(const unsigned char* p, size_t size, ImageFormat format, std::vector<unsigned char>* out,
                          std::string* why) {
  out->clear();
  if (format == ImageFormat::Png) {  // chunks already checked: length, type, data, CRC
    out->insert(out->end(), p, p + std::min<size_t>(size, 8));
    for (size_t at = 8; at + 12 <= size;) {
      const size_t next = at + 12 + size_t(be32(p + at));
      if (next > size) break;
      if (!std::equal(p + at + 4, p + at + 8, "iCCP")) out->insert(out->end(), p + at, p + next);
      at = next;
    }
    return true;
  }
  if (format != ImageFormat::Jpeg) {
    out->assign(p, p + size);
    return true;
  }
  // JPEG: SOI, then marker segments (FF, marker, 16-bit length counting itself) up to the
  // first SOS, whose entropy-coded data runs to the end: copied as it is.
  static const char icc[12] = {'I', 'C', 'C', '_', 'P', 'R', 'O', 'F', 'I', 'L', 'E', '\0'};
  out->insert(out->end(), p, p + 2);
  size_t at = 2;
  while (at < size) {
    if (p[at] != 0xFF || at + 1 >= size) {
      *why = "damaged JPEG: no marker at byte " + std::to_string(at);
      return false;
    }
    const unsigned char m = p[at + 1];
    if (m == 0xFF) {  // fill byte
      out->push_back(0xFF);
      ++at;
      continue;
    }
    if (m == 0xD8 || m == 0x01 || (m >= 0xD0 && m <= 0xD7)) {  // no length
      out->insert(out->end(), p + at, p + at + 2);
      at += 2;
      continue;
    }
    if (at + 4 > size) break;
    const size_t length = size_t(p[at + 2]) << 8 | p[at + 3];
    if (length < 2 || at + 2 + length > size) {
      *why = "damaged JPEG: the segment of marker " + std::to_string(m) + " at byte " + std::to_string(at) +
             " claims " + std::to_string(length) + " bytes, past the end of the data";
      return false;
    }
    const bool profile = m == 0xE2 && length >= 2 + sizeof icc && std::equal(icc, icc + sizeof icc, p + at + 4);
    if (m == 0xDA || m == 0xD9) {  // start of scan (or an early end of image): the rest as it is
      out->insert(out->end(), p + at, p + size);
      return true;
    }
    if (!profile) out->insert(out->end(), p + at, p + at + 2 + length);
    at += 2 + length;
  }
  *why = "truncated JPEG: it ends before its scan starts";
  return false;
}

std::string image_size_refusal(uint64_t width, uint64_t height, uint64_t max_dimension, uint64_t max_pixels,
                               const std::string& raise) {
  if (width <= max_dimension && height <= max_dimension && width * height <= max_pixels) return {};
  return "the image is " + std::to_string(width) + "x" + std::to_string(height) + ", larger than the limit of " +
         std::to_string(max_dimension) + " per side and " + std::to_string(max_pixels) + " pixels (" + raise + ")";
}

}  // namespace clpt
