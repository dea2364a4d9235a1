#include "util/atomic_file.h"

#include <fstream>
#include <system_error>
#include <unistd.h>

namespace clpt {
namespace fs = std::filesystem;

bool write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& fill,
                           std::string* why) {
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  const fs::path tmp = dir / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  std::error_code ec;
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    fill(f);
    if (!f.flush()) {
      fs::remove(tmp, ec);
      why->clear();
      return false;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    *why = ec.message();
    fs::remove(tmp, ec);
    return false;
  }
  return true;
}

}  // namespace clpt
