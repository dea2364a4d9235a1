// ViewTransform (host/io/view_transform.*): how PNG and JPEG show radiance (issue 24). The
// expected values are worked by hand from each transform's published definition (the
// arithmetic is in the comments), not taken from the implementation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "io/view_transform.h"

namespace clpt::view_transform_test {
namespace {

std::array<float, 3> encode(ViewTransform v, float r, float g, float b, float exposure = 0.0f) {
  return display_encode(DisplaySettings{v, exposure}, {r, g, b});
}
float grey(ViewTransform v, float x, float exposure = 0.0f) { return encode(v, x, x, x, exposure)[0]; }
float srgb(float v) { return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f; }

const ViewTransform kAll[] = {ViewTransform::Standard, ViewTransform::KhronosNeutral, ViewTransform::AgX,
                              ViewTransform::Aces};

TEST(ViewTransform, NamesRoundTrip) {
  for (ViewTransform v : kAll) EXPECT_EQ(parse_view_transform(view_transform_name(v)), v);
  EXPECT_FALSE(parse_view_transform("filmic"));
  EXPECT_FALSE(parse_view_transform(""));
}

// standard: clpt's output before --view: clamp, then the sRGB curve.
TEST(ViewTransform, StandardIsTheClampedSrgbCurve) {
  EXPECT_FLOAT_EQ(grey(ViewTransform::Standard, 0.0f), 0.0f);
  EXPECT_NEAR(grey(ViewTransform::Standard, 0.0031308f), 0.040449936f, 1e-6);
  EXPECT_NEAR(grey(ViewTransform::Standard, 0.5f), 0.735357f, 1e-5);
  EXPECT_FLOAT_EQ(grey(ViewTransform::Standard, 1.0f), 1.0f);
  EXPECT_FLOAT_EQ(grey(ViewTransform::Standard, 7.0f), 1.0f);
  EXPECT_FLOAT_EQ(grey(ViewTransform::Standard, -1.0f), 0.0f);
}

// Exposure is a factor of 2^EV before the transform, in every view.
TEST(ViewTransform, ExposureScalesRadianceFirst) {
  for (ViewTransform v : kAll)
    for (float x : {0.01f, 0.18f, 0.7f, 3.0f}) {
      SCOPED_TRACE(view_transform_name(v));
      EXPECT_FLOAT_EQ(grey(v, x, 1.0f), grey(v, 2.0f * x));
      EXPECT_FLOAT_EQ(grey(v, x, -2.0f), grey(v, 0.25f * x));
    }
}

// Khronos PBR Neutral by its specification (F90 = 0.04, Ks = 0.76, Kd = 0.15).
TEST(ViewTransform, KhronosNeutralFollowsItsSpecification) {
  // Grey 0.5: min 0.5 > 2 F90, so f = F90 = 0.04; peak 0.46 <= Ks: 0.46, unchanged.
  EXPECT_NEAR(grey(ViewTransform::KhronosNeutral, 0.5f), srgb(0.46f), 1e-6);
  // (0.2, 0.1, 0.05): f = 0.05 - 0.05^2 / 0.16 = 0.034375; peak 0.165625 <= Ks.
  const auto low = encode(ViewTransform::KhronosNeutral, 0.2f, 0.1f, 0.05f);
  EXPECT_NEAR(low[0], srgb(0.165625f), 1e-6);
  EXPECT_NEAR(low[1], srgb(0.065625f), 1e-6);
  EXPECT_NEAR(low[2], srgb(0.015625f), 1e-6);
  // Red 10: f = 0, p = 10, pn = 1 - 0.24^2 / (10 + 1 - 1.52) = 0.993924, g = 1 / (0.15 (p - pn)
  // + 1) = 0.425368: red p_n g + p_n (1 - g) = pn, green and blue pn (1 - g) = 0.571134.
  const auto red = encode(ViewTransform::KhronosNeutral, 10.0f, 0.0f, 0.0f);
  EXPECT_NEAR(red[0], srgb(0.993924f), 2e-5);
  EXPECT_NEAR(red[1], srgb(0.571134f), 2e-5);
  EXPECT_NEAR(red[2], red[1], 1e-7);
  // Very bright grey tends to white; infinity is white, NaN black.
  EXPECT_NEAR(grey(ViewTransform::KhronosNeutral, 1e6f), 1.0f, 1e-5);
  EXPECT_FLOAT_EQ(grey(ViewTransform::KhronosNeutral, std::numeric_limits<float>::infinity()), 1.0f);
  EXPECT_FLOAT_EQ(grey(ViewTransform::KhronosNeutral, std::nanf("")), 0.0f);
}

// AgX (Wrensch's fit): middle grey 0.18 sits at the sigmoid's pivot, log2(0.18) = -2.474 EV,
// (−2.474 + 12.474) / 16.5 = 0.60606, where the polynomial gives 0.4967 (its matrices keep
// grey grey to 1e-4): half-way up the display range. Black maps to 0, 16 EV above middle grey
// to the top of the curve (0.9987).
TEST(ViewTransform, AgxPivotsMiddleGreyToHalf) {
  EXPECT_NEAR(grey(ViewTransform::AgX, 0.18f), 0.4967f, 2e-3);
  EXPECT_NEAR(grey(ViewTransform::AgX, 0.0f), 0.0f, 1e-6);
  EXPECT_NEAR(grey(ViewTransform::AgX, 0.18f * 65536.0f), 0.9987f, 2e-3);
  const auto c = encode(ViewTransform::AgX, 0.18f, 0.18f, 0.18f);
  EXPECT_NEAR(c[0], c[1], 1e-3);
  EXPECT_NEAR(c[1], c[2], 1e-3);
  // Colours, which grey cannot check (a transposed matrix keeps grey grey): Wrensch's
  // matrices are GLSL mat3s, column by column; evaluated in that convention by a separate
  // python3 script from the published constants: red 1 -> (0.86098, 0.23016, 0.23032), a sky
  // blue (0.05, 0.2, 0.6) -> (0.35991, 0.52903, 0.72308).
  const auto red = encode(ViewTransform::AgX, 1.0f, 0.0f, 0.0f);
  EXPECT_NEAR(red[0], 0.86098f, 1e-4);
  EXPECT_NEAR(red[1], 0.23016f, 1e-4);
  EXPECT_NEAR(red[2], 0.23032f, 1e-4);
  const auto sky = encode(ViewTransform::AgX, 0.05f, 0.2f, 0.6f);
  EXPECT_NEAR(sky[0], 0.35991f, 1e-4);
  EXPECT_NEAR(sky[1], 0.52903f, 1e-4);
  EXPECT_NEAR(sky[2], 0.72308f, 1e-4);
}

// ACES in Hill's fit: both matrices' rows sum to 1, so grey stays grey, and the fit at 0.18
// is (0.18 (0.18 + 0.0245786) - 0.000090537) / (0.18 (0.983729 0.18 + 0.432951) + 0.238081)
// = 0.0367336 / 0.347885 = 0.105591 linear, 0.358 after the sRGB curve.
TEST(ViewTransform, AcesFitAtMiddleGrey) {
  EXPECT_NEAR(grey(ViewTransform::Aces, 0.18f), srgb(0.105591f), 2e-4);
  EXPECT_FLOAT_EQ(grey(ViewTransform::Aces, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(grey(ViewTransform::Aces, 1e6f), 1.0f);
}

// Every transform: outputs in [0, 1], and a grey ramp never gets darker as it gets brighter.
TEST(ViewTransform, GreyRampsAreMonotonicInRange) {
  for (ViewTransform v : kAll) {
    SCOPED_TRACE(view_transform_name(v));
    float last = -1.0f;
    for (float ev = -14.0f; ev <= 14.0f; ev += 0.125f) {
      const auto c = encode(v, 0.18f, 0.18f, 0.18f, ev);
      for (float x : c) {
        EXPECT_GE(x, 0.0f);
        EXPECT_LE(x, 1.0f);
      }
      EXPECT_GE(c[0], last - 1e-6f) << "at " << ev << " EV";
      last = c[0];
    }
  }
}

}  // namespace
}  // namespace clpt::view_transform_test
