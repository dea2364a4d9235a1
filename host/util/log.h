// Minimal leveled logging to stderr. Verbosity is process-wide and set once from options.
#pragma once

#include <string>

namespace clpt::log {

enum class Level { Quiet = 0, Normal = 1, Verbose = 2 };

void set_level(Level level);
Level level();

void info(const std::string& message);     // shown unless --quiet
void verbose(const std::string& message);  // shown with --verbose
void warn(const std::string& message);     // shown unless --quiet, prefixed "warning: "
void error(const std::string& message);    // always shown, prefixed "error: "

}  // namespace clpt::log
