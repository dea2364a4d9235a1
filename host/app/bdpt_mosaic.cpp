#include "app/bdpt_mosaic.h"

#include <algorithm>

namespace clpt {

MosaicResult render_bdpt_mosaic(const cl::Context& ctx, const Scene& scene, RenderSettings settings,
                                bool unweighted, const std::atomic<bool>* stop,
                                const std::function<void(uint32_t, uint32_t)>& progress) {
  struct Cell {
    uint32_t d, s;
  };
  std::vector<Cell> cells;
  for (uint32_t d = 0; d < kMosaicRows; ++d)
    for (uint32_t s = 0; s <= d + 1; ++s)
      if (!(s == 1 && d == 0)) cells.push_back({d, s});  // (1, 1) is not a bdpt strategy

  MosaicResult r;
  r.cells_total = static_cast<uint32_t>(cells.size());
  settings.integrator = "bdpt";
  settings.bdpt.unweighted = unweighted;
  if (settings.time_limit > 0.0) settings.time_limit /= double(cells.size());
  uint32_t w = 0, h = 0;
  for (const Cell& c : cells) {
    if (stop && stop->load()) {
      r.interrupted = true;
      break;
    }
    RenderSettings s = settings;
    s.max_depth = c.d;
    s.bdpt.strategy_s = c.s;
    s.bdpt.strategy_t = c.d + 2 - c.s;
    Renderer renderer(ctx, scene, s);
    const RenderOutput out = renderer.render(stop);
    if (r.image.rgb.empty()) {
      w = renderer.width();
      h = renderer.height();
      r.image = Image(w * kMosaicColumns, h * kMosaicRows);
      r.samples_per_pixel = out.film.samples_per_pixel;
    }
    r.samples_per_pixel = std::min(r.samples_per_pixel, out.film.samples_per_pixel);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k)
          r.image.rgb[(size_t(c.d * h + y) * r.image.width + c.s * w + x) * 3 + k] =
              out.film.mean.rgb[(size_t(y) * w + x) * 3 + k];
    ++r.cells_rendered;
    if (progress) progress(r.cells_rendered, r.cells_total);
    if (out.interrupted) {
      r.interrupted = true;
      break;
    }
  }
  return r;
}

}  // namespace clpt
