#include "io/hdr_codec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace clpt {

namespace {

constexpr size_t kMaxHeaderBytes = size_t{1} << 16;  // a real header is a few hundred bytes

// Parses the header; `pixels` gets the offset of the first scanline byte.
bool parse_header(const unsigned char* data, size_t size, uint64_t* width, uint64_t* height, size_t* pixels,
                  std::string* why) {
  if (size < 2 || data[0] != '#' || data[1] != '?') {
    *why = "not a Radiance HDR file (no \"#?\" signature)";
    return false;
  }
  const size_t limit = std::min(size, kMaxHeaderBytes);
  size_t at = 0;
  auto next_line = [&](std::string* line) {
    const void* nl = std::memchr(data + at, '\n', limit - at);
    if (!nl) return false;
    const size_t end = size_t(static_cast<const unsigned char*>(nl) - data);
    line->assign(reinterpret_cast<const char*>(data + at), end - at);
    at = end + 1;
    return true;
  };
  std::string line;
  bool format_seen = false;
  for (;;) {
    if (!next_line(&line)) {
      *why = "damaged Radiance HDR header: no empty line ends it within its first " +
             std::to_string(kMaxHeaderBytes) + " bytes";
      return false;
    }
    if (line.empty()) break;
    if (line.rfind("FORMAT=", 0) == 0) {
      if (line != "FORMAT=32-bit_rle_rgbe") {
        *why = "a Radiance HDR file of " + line.substr(0, 60) + " (clpt reads 32-bit_rle_rgbe)";
        return false;
      }
      format_seen = true;
    }
  }
  (void)format_seen;  // files without FORMAT= are RGBE by the format's default
  if (!next_line(&line)) {
    *why = "damaged Radiance HDR header: no resolution line";
    return false;
  }
  unsigned long long h = 0, w = 0;
  char extra = 0;
  if (std::sscanf(line.c_str(), "-Y %llu +X %llu%c", &h, &w, &extra) != 2) {
    *why = "a Radiance HDR resolution line clpt does not read: \"" + line.substr(0, 40) +
           "\" (clpt reads the standard orientation, \"-Y H +X W\")";
    return false;
  }
  *width = w;
  *height = h;
  *pixels = at;
  return true;
}

}  // namespace

bool hdr_header_size(const unsigned char* data, size_t size, uint64_t* width, uint64_t* height, std::string* why) {
  size_t pixels = 0;
  return parse_header(data, size, width, height, &pixels, why);
}

bool decode_hdr(const unsigned char* data, size_t size, const SizeCheck& check, Raster* out, DecodeFailure* fail) {
  uint64_t w = 0, h = 0;
  size_t at = 0;
  std::string why;
  if (!parse_header(data, size, &w, &h, &at, &why)) return fail->set(why, -1);
  if (w == 0 || h == 0) return fail->set("the Radiance HDR header gives a size of 0", -1);
  if (std::string refusal = check(w, h); !refusal.empty()) return fail->set(refusal, -1);
  out->width = uint32_t(w);
  out->height = uint32_t(h);
  out->channels = 3;
  out->type = SampleType::F32;
  out->bytes.clear();
  const size_t width = size_t(w);
  std::vector<unsigned char> scan(width * 4);  // RGBE texels of one row
  std::vector<float> row(width * 3);
  auto ends = [&](uint32_t y) { return fail->set("the pixel data ends in row " + std::to_string(y), y); };

  for (uint32_t y = 0; y < out->height; ++y) {
    if (y % kDecodeStripRows == 0)
      out->bytes.resize(size_t(std::min<uint64_t>(h, y + kDecodeStripRows)) * out->row_bytes());
    if (size - at < 4) return ends(y);
    const unsigned char* p = data + at;
    if (width >= 8 && width < 32768 && p[0] == 2 && p[1] == 2 && !(p[2] & 0x80)) {
      // New-style: the four components one after another, each as runs and literals.
      if ((size_t(p[2]) << 8 | p[3]) != width)
        return fail->set("damaged Radiance HDR: row " + std::to_string(y) + " gives a width of " +
                          std::to_string(size_t(p[2]) << 8 | p[3]) + ", the header " + std::to_string(width),
                      y);
      at += 4;
      for (int c = 0; c < 4; ++c) {
        size_t x = 0;
        while (x < width) {
          if (at >= size) return ends(y);
          unsigned count = data[at++];
          const bool run = count > 128;
          if (run) count -= 128;
          if (count == 0 || count > width - x)
            return fail->set("damaged Radiance HDR: a run of " + std::to_string(count) + " in row " + std::to_string(y) +
                              " does not fit its width",
                          y);
          if (run) {
            if (at >= size) return ends(y);
            const unsigned char v = data[at++];
            for (unsigned k = 0; k < count; ++k) scan[(x + k) * 4 + size_t(c)] = v;
          } else {
            if (size - at < count) return ends(y);
            for (unsigned k = 0; k < count; ++k) scan[(x + k) * 4 + size_t(c)] = data[at + k];
            at += count;
          }
          x += count;
        }
      }
    } else {
      // Flat texels, where (1, 1, 1, n) repeats the previous texel n << shift times (old style).
      size_t x = 0;
      int shift = 0;
      while (x < width) {
        if (size - at < 4) return ends(y);
        const unsigned char* t = data + at;
        at += 4;
        if (t[0] == 1 && t[1] == 1 && t[2] == 1) {
          if (x == 0 || shift > 24)
            return fail->set("damaged Radiance HDR: a run with nothing to repeat in row " + std::to_string(y), y);
          const size_t count = size_t(t[3]) << shift;
          if (count > width - x)
            return fail->set("damaged Radiance HDR: a run in row " + std::to_string(y) + " does not fit its width", y);
          for (size_t k = 0; k < count; ++k) std::memcpy(&scan[(x + k) * 4], &scan[(x - 1) * 4], 4);
          x += count;
          shift += 8;
        } else {
          std::memcpy(&scan[x * 4], t, 4);
          ++x;
          shift = 0;
        }
      }
    }
    for (size_t x = 0; x < width; ++x) {
      const unsigned char* t = &scan[x * 4];
      const float f = t[3] == 0 ? 0.0f : std::ldexp(1.0f, int(t[3]) - (128 + 8));
      for (int c = 0; c < 3; ++c) row[x * 3 + size_t(c)] = float(t[c]) * f;
    }
    std::memcpy(out->bytes.data() + size_t(y) * out->row_bytes(), row.data(), out->row_bytes());
  }
  return true;
}

}  // namespace clpt
