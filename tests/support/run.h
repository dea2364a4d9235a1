// Runs the clpt executable as a user would, capturing exit code, stdout and stderr.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace clpt::test {

struct RunResult {
  int exit_code = -1;  // -1 when it did not exit normally (e.g. crashed)
  std::string out, err;
  long max_rss_kib = 0;  // the child's peak resident memory (getrusage's ru_maxrss)
};

struct RunOptions {
  std::vector<std::pair<std::string, std::string>> env;  // set in the child only
  std::string interrupt_after;  // if not empty: SIGINT `delay` s after stderr first shows it
  double delay = 1.0;
  int interrupts = 1;             // SIGINTs to send, `interval` s apart
  double interval = 0.2;
};

// Runs `binary` with args (no shell involved), stdin from /dev/null.
RunResult run_program(const std::string& binary, const std::vector<std::string>& args,
                      const RunOptions& options = {});

// Runs CLPT_BINARY. If `interrupt_after` is not empty, sends SIGINT `delay` seconds after the
// program's stderr first contains that text.
RunResult run_clpt(const std::vector<std::string>& args, const std::string& interrupt_after = "",
                   double delay = 1.0);

std::string read_file(const std::string& path);

// Runs clpt on the glTF file `scene` with `--device pocl -q`, `args`, and
// `-o dir/name.exr --stats dir/name.json`; a failed run is a test failure (with its stderr).
// Returns the statistics (null when the run failed).
nlohmann::json run_clpt_stats(const std::filesystem::path& dir, const std::string& name,
                              const std::string& scene, const std::vector<std::string>& args);

}  // namespace clpt::test
