#include "render/cluster.h"

#include <new>

#include "util/error.h"

namespace clpt {
namespace {

// An exception as clpt reports it: its exit code and message (render/cluster.h).
std::pair<int, std::string> describe(std::exception_ptr e) {
  try {
    std::rethrow_exception(e);
  } catch (const Error& x) {
    return {static_cast<int>(x.code()), x.what()};
  } catch (const std::bad_alloc&) {
    return {static_cast<int>(ExitCode::Device), "out of host memory"};
  } catch (const std::exception& x) {
    return {70, std::string("internal error: ") + x.what()};
  } catch (...) {
    return {70, "internal error"};
  }
}

}  // namespace

std::exception_ptr capture(const std::function<void()>& f) {
  try {
    f();
  } catch (...) {
    return std::current_exception();
  }
  return nullptr;
}

std::string Cluster::all_gather_bytes(std::string mine) const {
  if (size() == 1) return mine;
  std::string all = root() ? mine : std::string();
  gather_text_to_root(mine, [&](const std::string& theirs) { all += theirs; });
  broadcast(all, 0);
  return all;
}

void Cluster::agree(std::exception_ptr mine) const {
  if (size() == 1) {
    if (mine) std::rethrow_exception(mine);
    return;
  }
  const std::pair<int, std::string> d = mine ? describe(mine) : std::pair<int, std::string>{0, ""};
  const std::vector<double> codes = all_gather({mine ? double(d.first) : -1.0});
  for (int r = 0; r < int(codes.size()); ++r) {
    if (codes[r] < 0.0) continue;
    std::string message = d.second;
    broadcast(message, r);
    const int code = static_cast<int>(codes[r]);
    const std::string where = r == 0 ? "" : "rank " + std::to_string(r) + ": ";
    throw Error(static_cast<ExitCode>(code), where + message);
  }
}

}  // namespace clpt
