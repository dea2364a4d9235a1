#include "scene/load_limits.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <utility>

#include "util/error.h"

namespace clpt {
namespace {

// The limits by name, in --limit's spelling.
std::vector<std::pair<const char*, uint64_t LoadLimits::*>> fields() {
  return {{"file-bytes", &LoadLimits::file_bytes},
          {"total-bytes", &LoadLimits::total_bytes},
          {"json-depth", &LoadLimits::json_depth},
          {"accessor-count", &LoadLimits::accessor_count},
          {"zero-accessor-count", &LoadLimits::zero_accessor_count},
          {"vertices", &LoadLimits::vertices},
          {"triangles", &LoadLimits::triangles},
          {"node-depth", &LoadLimits::node_depth},
          {"node-visits", &LoadLimits::node_visits},
          {"image-dimension", &LoadLimits::image_dimension},
          {"image-pixels", &LoadLimits::image_pixels},
          {"total-texels", &LoadLimits::total_texels},
          {"memory", &LoadLimits::memory_bytes},
          {"memory-per-file-byte", &LoadLimits::memory_per_file_byte}};
}

bool parse_count(const std::string& text, uint64_t* out) {
  if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return false;
  size_t i = 0;
  uint64_t v = 0;
  for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
    const uint64_t d = uint64_t(text[i] - '0');
    if (v > (UINT64_MAX - d) / 10) return false;
    v = v * 10 + d;
  }
  int shift = 0;
  if (i + 1 == text.size()) {
    switch (text[i]) {
      case 'k': case 'K': shift = 10; break;
      case 'M': shift = 20; break;
      case 'G': shift = 30; break;
      default: return false;
    }
  } else if (i != text.size()) {
    return false;
  }
  if (shift && v > (UINT64_MAX >> shift)) return false;
  *out = v << shift;
  return true;
}

}  // namespace

void LoadLimits::set(const std::string& spec) {
  const size_t eq = spec.find('=');
  std::string names;
  for (const auto& f : fields()) names += std::string(names.empty() ? "" : ", ") + f.first;
  if (eq == std::string::npos)
    throw Error(ExitCode::Usage, "--limit " + spec + ": expected NAME=VALUE (names: " + names + ")");
  const std::string name = spec.substr(0, eq), value = spec.substr(eq + 1);
  for (const auto& f : fields()) {
    if (name != f.first) continue;
    uint64_t v = 0;
    if (!parse_count(value, &v))
      throw Error(ExitCode::Usage, "--limit " + spec + ": '" + value +
                                       "' is not a non-negative integer (k, M, G suffixes allowed)");
    // The JSON parser and the node walk recurse once per level: a depth the stack cannot
    // hold would crash (issue 23, class 5: node-depth=1000000 and json-depth=2000000 ended in
    // SIGSEGV). Refuse it, naming the stack and what to do.
    if ((f.second == &LoadLimits::json_depth || f.second == &LoadLimits::node_depth) &&
        v > max_recursion_depth())
      throw Error(ExitCode::Usage,
                  "--limit " + spec + ": deeper than this process's stack (" +
                      std::to_string(stack_bytes() >> 10) + " KiB) can walk safely: at most " +
                      std::to_string(max_recursion_depth()) + " (raise the stack with ulimit -s)");
    this->*f.second = v;
    return;
  }
  throw Error(ExitCode::Usage, "--limit " + spec + ": unknown limit '" + name + "' (names: " + names + ")");
}

uint64_t LoadLimits::stack_bytes() {
  rlimit r{};
  if (::getrlimit(RLIMIT_STACK, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return uint64_t{1} << 30;
  return uint64_t(r.rlim_cur);
}

uint64_t LoadLimits::max_recursion_depth() { return stack_bytes() / kStackBytesPerLevel; }

std::string LoadLimits::describe() const {
  std::string s;
  for (const auto& f : fields()) s += std::string(f.first) + "=" + std::to_string(this->*f.second) + "\n";
  return s;
}

uint64_t LoadLimits::memory_budget() const {
  if (memory_bytes > 0) return memory_bytes;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return UINT64_MAX;
  return uint64_t(pages) / 10 * 8 * uint64_t(page);
}

uint64_t LoadLimits::memory_budget(uint64_t file_bytes, std::string* which) const {
  const uint64_t absolute = memory_budget();
  const unsigned __int128 scaled = (unsigned __int128)memory_per_file_byte * file_bytes;
  const uint64_t relative =
      std::max<uint64_t>(kMinMemoryBudget, scaled > UINT64_MAX ? UINT64_MAX : uint64_t(scaled));
  if (relative < absolute) {
    if (which)
      *which = std::to_string(memory_per_file_byte) + " bytes per byte of the scene's " + std::to_string(file_bytes) +
               " bytes of files, at least 256 MiB; --limit memory-per-file-byte=N changes it";
    return relative;
  }
  if (which)
    *which = std::string(memory_bytes ? "--limit memory" : "80 % of this machine's memory") +
             "; --limit memory=BYTES changes it";
  return absolute;
}

}  // namespace clpt
