// Writing a file so that nothing half-written is ever seen under its name.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace clpt {

// Writes `path` through a temporary file in the same folder ("." + name + ".tmp" + pid) that
// `fill` writes, then renamed over `path`: readers see the old file or the whole new one, and
// a failed write leaves neither a half file nor the temporary. Returns false when it failed,
// with *why the rename's reason (empty when writing the temporary failed).
bool write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& fill, std::string* why);

}  // namespace clpt
