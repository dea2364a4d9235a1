#include "util/log.h"

#include <atomic>
#include <cstdio>

namespace clpt::log {
namespace {
std::atomic<Level> g_level{Level::Normal};

void emit(const char* prefix, const std::string& message) {
  std::fprintf(stderr, "%s%s\n", prefix, message.c_str());
}
}  // namespace

void set_level(Level level) { g_level = level; }
Level level() { return g_level; }

void info(const std::string& message) {
  if (g_level >= Level::Normal) emit("", message);
}
void verbose(const std::string& message) {
  if (g_level >= Level::Verbose) emit("", message);
}
void warn(const std::string& message) {
  if (g_level >= Level::Normal) emit("warning: ", message);
}
void error(const std::string& message) { emit("error: ", message); }

}  // namespace clpt::log
