#include "render/mipmaps.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "util/srgb.h"

namespace clpt {

namespace {

const std::array<float, 256>& srgb_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      t[size_t(i)] = float(srgb_to_linear(i / 255.0));
    }
    return t;
  }();
  return table;
}

// A linear value in [0, 1] as an integer channel of `max` steps (255 or 65535), sRGB-encoded
// first where `srgb`.
uint32_t encode(double linear, bool srgb, double max) {
  double c = std::clamp(linear, 0.0, 1.0);
  if (srgb) c = linear_to_srgb(c);
  return uint32_t(std::lround(std::clamp(c, 0.0, 1.0) * max));
}

// Level k + 1 from level k (w x h), averaged in linear values; `wide`: 16 bits a channel, two
// words a texel (Texture::wide).
std::vector<uint32_t> halve(const std::vector<uint32_t>& src, uint32_t w, uint32_t h, bool srgb, bool wide) {
  const uint32_t w2 = std::max(1u, w / 2), h2 = std::max(1u, h / 2);
  const std::array<float, 256>& lut = srgb_table();
  const size_t words = wide ? 2 : 1;
  std::vector<uint32_t> out(size_t(w2) * h2 * words);
  for (uint32_t j = 0; j < h2; ++j) {
    const uint32_t y0 = uint32_t(uint64_t(j) * h / h2), y1 = uint32_t(uint64_t(j + 1) * h / h2);
    for (uint32_t i = 0; i < w2; ++i) {
      const uint32_t x0 = uint32_t(uint64_t(i) * w / w2), x1 = uint32_t(uint64_t(i + 1) * w / w2);
      double sum[4] = {0.0, 0.0, 0.0, 0.0};
      for (uint32_t y = y0; y < y1; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
          const size_t t = size_t(y) * w + x;
          if (wide) {
            const uint32_t c[4] = {src[2 * t] & 65535u, src[2 * t] >> 16, src[2 * t + 1] & 65535u,
                                   src[2 * t + 1] >> 16};
            for (int k = 0; k < 3; ++k) sum[k] += srgb ? srgb_to_linear(c[k] / 65535.0) : c[k] / 65535.0;
            sum[3] += c[3] / 65535.0;
            continue;
          }
          const uint32_t c = src[t];
          for (int k = 0; k < 3; ++k) {
            const uint32_t v = (c >> (8 * k)) & 255u;
            sum[k] += srgb ? double(lut[v]) : v / 255.0;
          }
          sum[3] += (c >> 24) / 255.0;
        }
      const double n = double(x1 - x0) * double(y1 - y0);
      const size_t o = size_t(j) * w2 + i;
      if (wide) {
        out[2 * o] = encode(sum[0] / n, srgb, 65535.0) | encode(sum[1] / n, srgb, 65535.0) << 16;
        out[2 * o + 1] = encode(sum[2] / n, srgb, 65535.0) | encode(sum[3] / n, false, 65535.0) << 16;
      } else {
        out[o] = encode(sum[0] / n, srgb, 255.0) | encode(sum[1] / n, srgb, 255.0) << 8 |
                 encode(sum[2] / n, srgb, 255.0) << 16 | encode(sum[3] / n, false, 255.0) << 24;
      }
    }
  }
  return out;
}

}  // namespace

std::vector<uint32_t> build_mip_levels(const std::vector<uint32_t>& texels, uint32_t width, uint32_t height,
                                       bool srgb, uint32_t* levels, bool wide) {
  std::vector<uint32_t> all;
  *levels = 1;
  if (width == 0 || height == 0 || texels.size() != size_t(width) * height * (wide ? 2 : 1)) return all;
  std::vector<uint32_t> level = texels;
  uint32_t w = width, h = height;
  while (w > 1 || h > 1) {
    level = halve(level, w, h, srgb, wide);
    w = std::max(1u, w / 2);
    h = std::max(1u, h / 2);
    all.insert(all.end(), level.begin(), level.end());
    ++*levels;
  }
  return all;
}

std::vector<bool> textures_read_as_srgb(const Scene& scene) {
  std::vector<bool> srgb(scene.textures.size(), false);
  auto mark = [&](const TextureRef& r) {
    if (r.used() && size_t(r.texture) < srgb.size()) srgb[size_t(r.texture)] = true;
  };
  for (const Material& m : scene.materials) {
    mark(m.base_color_texture);
    mark(m.emissive_texture);
    mark(m.specular_color_texture);
    mark(m.sheen_color_texture);
    mark(m.diffuse_transmission_color_texture);
  }
  return srgb;
}

}  // namespace clpt
