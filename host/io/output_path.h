// Up-front checks of the files a run will write (image, statistics, checkpoint), so that a
// render of hours does not end in "cannot write".
#pragma once

#include <filesystem>
#include <string>

namespace clpt {

// Throws Error(ExitCode::Output) naming `what` ("output", "--stats", ...) and the path when
// `path` cannot be written: its folder does not exist, is a file, or refuses a new file (a
// probe file is created there and removed: this catches read-only file systems, /proc and
// folders that permissions close even when access() would say yes), or the path is a folder.
void check_writable_path(const std::filesystem::path& path, const std::string& what);

}  // namespace clpt
