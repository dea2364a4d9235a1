// The clpt program: options -> scene -> device -> render -> image (and --stats JSON).
#pragma once

namespace clpt {

class Cluster;

// Runs the command line; returns the process exit code (see util/error.h). cluster: the MPI
// ranks this process renders with (render/cluster.h), every rank running the same command
// line; only rank 0 prints and writes. Null: this process alone.
int run_cli(int argc, const char* const* argv, const Cluster* cluster = nullptr);

}  // namespace clpt
