#include "io/output_path.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "util/error.h"

namespace clpt {

namespace fs = std::filesystem;

void check_writable_path(const fs::path& path, const std::string& what) {
  const std::string name = what + " " + path.string();
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!fs::exists(st))
    throw Error(ExitCode::Output, name + ": folder " + dir.string() + " does not exist");
  if (!fs::is_directory(st))
    throw Error(ExitCode::Output, name + ": " + dir.string() + " is a file, not a folder");
  if (fs::is_directory(path, ec)) throw Error(ExitCode::Output, name + " is a folder");
  // Create (and remove) a file beside the target: the only test every file system answers
  // truthfully (access() says yes to root on read-only mounts and on /proc).
  const fs::path probe = dir / (".clpt-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const int err = errno;
    throw Error(ExitCode::Output, name + ": cannot create files in " + dir.string() + " (" +
                                      std::strerror(err) + ")");
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace clpt
