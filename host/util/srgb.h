// The sRGB transfer function (IEC 61966-2-1) and its inverse in double precision, for the
// host's texture work (mip levels, the light table's emissive textures, clpt-diff's maps);
// kernels/texture/texture.cl has the device's. (Image reading and the view transform keep
// their float versions: their results are part of what images and tests compare.)
#pragma once

#include <cmath>

namespace clpt {

inline double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

inline double linear_to_srgb(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace clpt
