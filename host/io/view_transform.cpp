#include "io/view_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clpt {
namespace {

using Rgb = std::array<float, 3>;
using Mat = std::array<std::array<double, 3>, 3>;  // rows: out[i] = sum_j m[i][j] in[j]

Rgb mul(const Mat& m, const Rgb& v) {
  Rgb out{};
  for (int i = 0; i < 3; ++i) out[i] = float(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2]);
  return out;
}

float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }  // NaN -> 0

// IEC 61966-2-1 sRGB encoding of a display-linear value in [0, 1].
float srgb_oetf(float v) {
  v = clamp01(v);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// Khronos PBR Neutral, as its specification writes it (KhronosGroup/ToneMapping,
// PBR_Neutral/README.md): F90 = 0.04, Ks = 0.8 - F90, Kd = 0.15.
Rgb khronos_neutral(Rgb c) {
  const float f90 = 0.04f, ks = 0.8f - f90, kd = 0.15f;
  const float x = std::min({c[0], c[1], c[2]});
  const float f = x <= 2.0f * f90 ? x - x * x / (4.0f * f90) : f90;
  for (float& v : c) v -= f;
  const float p = std::max({c[0], c[1], c[2]});
  if (p <= ks) return c;
  const float pn = 1.0f - (1.0f - ks) * (1.0f - ks) / (p + 1.0f - 2.0f * ks);
  const float g = 1.0f / (kd * (p - pn) + 1.0f);
  for (float& v : c) v = v * (pn / p) * g + pn * (1.0f - g);
  return c;
}

// AgX in Wrensch's fit: the inset matrix, log2 between -12.47393 and +4.026069 EV around
// middle grey (16.5 stops), a 6th-order polynomial for AgX's default contrast curve, the
// outset (inverse inset) matrix; the result is already display-encoded.
Rgb agx(const Rgb& c) {
  static const Mat inset = {{{0.842479062253094, 0.0784335999999992, 0.0792237451477643},
                             {0.0423282422610123, 0.878468636469772, 0.0791661274605434},
                             {0.0423756549057051, 0.0784336, 0.879142973793104}}};
  static const Mat outset = {{{1.19687900512017, -0.0980208811401368, -0.0990297440797205},
                              {-0.0528968517574562, 1.15190312990417, -0.0989611768448433},
                              {-0.0529716355144438, -0.0980434501171241, 1.15107367264116}}};
  const double min_ev = -12.47393, max_ev = 4.026069;
  Rgb v = mul(inset, c);
  for (float& x : v) {
    const double e = std::clamp(std::log2(std::max(double(x), 1e-10)), min_ev, max_ev);
    const double t = (e - min_ev) / (max_ev - min_ev), t2 = t * t, t4 = t2 * t2;
    x = float(15.5 * t4 * t2 - 40.14 * t4 * t + 31.96 * t4 - 6.868 * t2 * t + 0.4298 * t2 + 0.1191 * t - 0.00232);
  }
  v = mul(outset, v);
  for (float& x : v) x = clamp01(x);
  return v;
}

// ACES RRT + sRGB ODT in Hill's fit: to the RRT's working space (with its saturation), a
// rational fit of RRT + ODT per channel, back to linear sRGB.
Rgb aces(const Rgb& c) {
  static const Mat input = {{{0.59719, 0.35458, 0.04823}, {0.07600, 0.90834, 0.01566}, {0.02840, 0.13383, 0.83777}}};
  static const Mat output = {
      {{1.60475, -0.53108, -0.07367}, {-0.10208, 1.10813, -0.00605}, {-0.00327, -0.07276, 1.07602}}};
  Rgb v = mul(input, c);
  for (float& x : v) {
    const double d = x;
    x = float((d * (d + 0.0245786) - 0.000090537) / (d * (0.983729 * d + 0.4329510) + 0.238081));
  }
  return mul(output, v);
}

}  // namespace

std::optional<ViewTransform> parse_view_transform(const std::string& name) {
  for (ViewTransform v : {ViewTransform::Standard, ViewTransform::KhronosNeutral, ViewTransform::AgX, ViewTransform::Aces})
    if (name == view_transform_name(v)) return v;
  return std::nullopt;
}

const char* view_transform_name(ViewTransform view) {
  switch (view) {
    case ViewTransform::Standard: return "standard";
    case ViewTransform::KhronosNeutral: return "khronos-neutral";
    case ViewTransform::AgX: return "agx";
    case ViewTransform::Aces: return "aces";
  }
  return "standard";
}

std::array<float, 3> display_encode(const DisplaySettings& display, const std::array<float, 3>& rgb) {
  const float scale = std::exp2(display.exposure);
  Rgb c;
  for (int i = 0; i < 3; ++i) {
    const float v = rgb[i] * scale;  // +inf is the brightest there is; NaN and v <= 0 are black
    c[i] = v > 0.0f ? std::min(v, std::numeric_limits<float>::max()) : 0.0f;
  }
  switch (display.view) {
    case ViewTransform::Standard: break;
    case ViewTransform::KhronosNeutral: c = khronos_neutral(c); break;
    case ViewTransform::AgX: return agx(c);
    case ViewTransform::Aces: c = aces(c); break;
  }
  return {srgb_oetf(c[0]), srgb_oetf(c[1]), srgb_oetf(c[2])};
}

}  // namespace clpt
