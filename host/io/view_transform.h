// View transforms: how 8-bit output (PNG, JPEG) shows linear scene radiance (issue 24). An
// EXR stays linear scene radiance; the transform and exposure go into every file's metadata.
//   standard         clamp to [0, 1], then the sRGB curve (clpt's output before --view)
//   khronos-neutral  Khronos PBR Neutral (Khronos Group, 2024): base colours shown faithfully
//                    up to a highlight compression that starts at 0.76 and desaturates above
//   agx              Troy Sobotka's AgX as Blender 4 shows it by default, through Benjamin
//                    Wrensch's analytic fit ("Minimal AgX implementation", 2023): a log2
//                    encoding of 16.5 stops around middle grey and a polynomial sigmoid
//   aces             the ACES reference rendering and sRGB output transforms (RRT + ODT) in
//                    Stephen Hill's fit (BakingLab, 2016), as most game engines use it
// Each takes linear Rec. 709 radiance times 2^exposure and gives display-encoded values in
// [0, 1], ready to quantise.
#pragma once

#include <array>
#include <optional>
#include <string>

namespace clpt {

enum class ViewTransform { Standard, KhronosNeutral, AgX, Aces };

// "standard", "khronos-neutral", "agx", "aces"; nullopt for anything else.
std::optional<ViewTransform> parse_view_transform(const std::string& name);
const char* view_transform_name(ViewTransform view);

struct DisplaySettings {
  ViewTransform view = ViewTransform::Standard;
  float exposure = 0.0f;  // EV: the radiance is multiplied by 2^exposure first
};

// The display-encoded colour of linear Rec. 709 radiance `rgb` (negative and non-finite
// components count as 0).
std::array<float, 3> display_encode(const DisplaySettings& display, const std::array<float, 3>& rgb);

}  // namespace clpt
