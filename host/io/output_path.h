// Up-front checks of the files a run will write (image, statistics, checkpoint), so that a
// render of hours does not end in "cannot write".
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace clpt {

// Throws Error(ExitCode::Output) naming `what` ("output", "--stats", ...) and the path when
// `path` cannot be written: its folder does not exist, is a file, or refuses a new file (a
// probe file is created there and removed: this catches read-only file systems, /proc and
// folders that permissions close even when access() would say yes), or the path is a folder.
// Also when the path exists and is not a regular file (a device, FIFO or socket, or a link to
// one): the write's final rename would replace that node.
void check_writable_path(const std::filesystem::path& path, const std::string& what);

// Throws Error(ExitCode::BadInput) naming `what` and the path when the path exists and is not
// a regular file (a FIFO, a device, a socket, a folder, or a link to one): reading a FIFO or
// /dev/zero waits or runs forever (issue 23, class 2). A missing file is left to the reader,
// whose message says so.
void check_regular_input(const std::filesystem::path& path, const std::string& what);

// Whether a and b are one file: the same inode where both exist, else the same normalised
// absolute path.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// A file the run reads or writes, with the option that names it ("--stats", "the scene").
using NamedPath = std::pair<std::string, std::filesystem::path>;

// Throws Error(ExitCode::Usage) when an output is one of the run's inputs (--stats scene.gltf
// used to overwrite the scene) or two outputs are one file; `allowed` lists (output, input)
// pairs that may be one file (--checkpoint and --resume: the checkpoint is read whole before
// the first write, and rewriting it is how a render continues).
void check_outputs_apart(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs,
                         const std::vector<std::pair<std::string, std::string>>& allowed = {});

}  // namespace clpt
