// The clpt program: options -> scene -> device -> render -> image (and --stats JSON).
#pragma once

namespace clpt {

// Runs the command line; returns the process exit code (see util/error.h).
int run_cli(int argc, const char* const* argv);

}  // namespace clpt
