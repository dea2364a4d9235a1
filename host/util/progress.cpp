#include "util/progress.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace clpt {

void ProgressBar::update(uint64_t done, uint64_t target, double elapsed, double limit,
                         const std::string& note) {
  if (!enabled_) return;
  double fraction = 0.0;
  if (target) fraction = double(done) / double(target);
  if (limit > 0.0) fraction = std::max(fraction, std::min(1.0, elapsed / limit));
  fraction = std::min(1.0, fraction);
  if (elapsed - last_draw_ < 0.1 && fraction < 1.0) return;  // at most 10 redraws a second
  last_draw_ = elapsed;
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width);
  std::string bar(filled, '=');
  if (filled < width) bar += '>' + std::string(width - filled - 1, ' ');
  const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r[%s] %3d%%  %llu%s spp  %.1f s  ETA %.1f s  %s   ", bar.c_str(),
               static_cast<int>(fraction * 100.0), static_cast<unsigned long long>(done),
               target ? ("/" + std::to_string(target)).c_str() : "", elapsed, eta, note.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace clpt
