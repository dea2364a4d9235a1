// The --stats document: what a render did and cost, as JSON (docs/stats.md lists its keys).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>

#include "cl/device.h"
#include "io/image.h"
#include "options.h"
#include "render/renderer.h"

namespace clpt {

// out: the render's film and statistics at width x height; load_seconds: the scene's load;
// reference: the --reference image (its errors are reported), or nullptr.
nlohmann::json stats_document(const Options& opt, const cl::DeviceInfo& device, const RenderOutput& out,
                              uint32_t width, uint32_t height, double load_seconds,
                              const Image* reference);

}  // namespace clpt
