// The strategies of bidirectional path tracing side by side (--bdpt-mosaic), the debugging
// view pbrt's BDPT writes as separate images: row d holds paths of d bounces (0 to 4, so
// paths of up to 5 segments), column s the strategy with s light vertices and
// t = d + 2 - s camera vertices. Each cell is that strategy alone at the render's
// resolution, MIS-weighted (the cells of a row add up to the light of d-bounce paths) or,
// with unweighted, each converging on its own to that light. Cells without a strategy
// (s > d + 1, and s = 1, t = 1) stay black.
#pragma once

#include <atomic>
#include <functional>

#include "cl/context.h"
#include "io/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt {

constexpr uint32_t kMosaicRows = 5, kMosaicColumns = 6;

struct MosaicResult {
  Image image;                 // kMosaicColumns x kMosaicRows cells
  uint32_t cells_rendered = 0;
  uint32_t cells_total = 0;
  uint64_t samples_per_pixel = 0;  // of each cell
  bool interrupted = false;
};

// settings: the render's (integrator bdpt, resolution, spp or time); the strategy and depth
// are set per cell, a time limit is split evenly over the cells. progress(cell, cells).
MosaicResult render_bdpt_mosaic(const cl::Context& ctx, const Scene& scene, RenderSettings settings,
                                bool unweighted, const std::atomic<bool>* stop,
                                const std::function<void(uint32_t, uint32_t)>& progress = {});

}  // namespace clpt
