// Runs the clpt executable as a user would, capturing exit code, stdout and stderr.
#pragma once

#include <string>
#include <vector>

namespace clpt::test {

struct RunResult {
  int exit_code = -1;  // -1 when it did not exit normally (e.g. crashed)
  std::string out, err;
};

// Runs CLPT_BINARY with args (no shell involved). If `interrupt_after` is not empty, sends
// SIGINT `delay` seconds after the program's stderr first contains that text.
RunResult run_clpt(const std::vector<std::string>& args, const std::string& interrupt_after = "",
                   double delay = 1.0);

std::string read_file(const std::string& path);

}  // namespace clpt::test
