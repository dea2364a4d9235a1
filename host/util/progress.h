// A one-line progress bar on stderr, redrawn in place; only used when stderr is a terminal.
#pragma once

#include <cstdint>
#include <string>

namespace clpt {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  ~ProgressBar() { finish(); }
  // done/target samples (target 0: unknown), elapsed and limit seconds (limit 0: none).
  // `note` is appended to the line (e.g. the current relMSE against a reference).
  void update(uint64_t done, uint64_t target, double elapsed, double limit,
              const std::string& note = {});
  void finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  double last_draw_ = -1.0;
};

}  // namespace clpt
