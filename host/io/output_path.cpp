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
  // The file is written beside the target and renamed over it: over a device, a FIFO or a
  // socket (or a link to one) that would replace the node itself (as root, --stats /dev/null
  // replaced /dev/null with a regular file).
  const fs::file_status target = fs::status(path, ec);
  if (fs::exists(target) && !fs::is_regular_file(target))
    throw Error(ExitCode::Output, name + " is not a regular file (a device, FIFO or socket): "
                                         "clpt writes only regular files");
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

void check_regular_input(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw Error(ExitCode::BadInput,
                what + path.string() + ": not a regular file (" +
                    (fs::is_directory(st) ? "a folder" : "a FIFO, device or socket") + ")");
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec) && !ec;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
  return !ec && ca == cb;
}

void check_outputs_apart(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs,
                         const std::vector<std::pair<std::string, std::string>>& allowed) {
  auto allowed_pair = [&](const std::string& out, const std::string& in) {
    for (const auto& [o, i] : allowed)
      if (o == out && i == in) return true;
    return false;
  };
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& [what, path] = outputs[i];
    for (const auto& [in_what, in_path] : inputs)
      if (!allowed_pair(what, in_what) && same_file(path, in_path))
        throw Error(ExitCode::Usage, what + " " + path.string() + " is " + in_what +
                                         ", an input of this run: it would be overwritten");
    for (size_t j = i + 1; j < outputs.size(); ++j)
      if (same_file(path, outputs[j].second))
        throw Error(ExitCode::Usage, what + " and " + outputs[j].first + " name the same file (" +
                                         path.string() + "): one would overwrite the other");
  }
}

}  // namespace clpt
