// The command line parsed in-process, for tests of usage errors without starting clpt.
#pragma once

#include <vector>

#include "util/error.h"

namespace clpt::test {

// parse_options on "clpt" followed by args: the Error's exit code, or Ok when it parses
// (also for --help and --version, which return without options).
ExitCode parse_error(std::vector<const char*> args);

}  // namespace clpt::test
