#include "app/cli.h"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <optional>
#include <unistd.h>

#include "app/render_job.h"
#include "render/cluster.h"
#include "cl/device.h"
#include "cl/programs.h"
#include "options.h"
#include "util/error.h"
#include "util/log.h"
#include "util/progress.h"

namespace clpt {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_signal(int) {
  // First signal: finish the pass in flight and save. Second: leave at once, output untouched.
  if (g_stop.exchange(true)) _exit(static_cast<int>(ExitCode::Interrupted));
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int run(const Options& opt, const Cluster& cluster) {
  const bool root = cluster.root();  // under mpirun, rank 0 alone prints and writes
  if (opt.list_devices) {
    if (root) std::cout << "OpenCL devices:\n" << cl::describe_devices(cl::list_devices());
    return 0;
  }
  install_signal_handlers();  // from here on, Ctrl-C stops cleanly and saves what was rendered
  if (!opt.kernel_dir.empty()) ::setenv("CLPT_KERNEL_DIR", opt.kernel_dir.c_str(), 1);
  if (!opt.dump_kernels.empty()) {
    if (!root) return 0;
    const size_t n = programs::dump(opt.dump_kernels);
    log::info("wrote " + std::to_string(n) + " kernel programs and programs.tsv to " +
              opt.dump_kernels);
    return 0;
  }
  // Under mpirun every rank sets up its own job; one that fails (a scene missing on its node)
  // makes all of them exit with its error.
  std::unique_ptr<RenderJob> job_owner;
  cluster.agree(capture([&] { job_owner = std::make_unique<RenderJob>(opt, /*writes_image=*/true, &cluster); }));
  RenderJob& job = *job_owner;

  // Progress: a bar on a terminal; with --reference, the relMSE so far (the job's note), on
  // the bar or as log lines when stderr is not a terminal.
  const bool tty = ::isatty(STDERR_FILENO);
  ProgressBar bar(root && log::level() >= log::Level::Normal && tty);
  const JobResult result = job.run(&g_stop, [&](uint64_t done, uint64_t target, double t, const std::string& note) {
    if (opt.bdpt_mosaic) {
      bar.update(done, target, t, 0.0, note);
      return;
    }
    if (!note.empty() && !tty) log::info(std::to_string(done) + " spp, " + std::to_string(t) + " s: " + note);
    bar.update(done, target, t, opt.time_limit, note);
  });
  bar.finish();
  cluster.agree(capture([&] {
    if (!root) return;
    write_job_image(opt, result);
    if (opt.stats) write_job_stats(*opt.stats, result.stats);
  }));
  return result.interrupted ? static_cast<int>(ExitCode::Interrupted) : 0;
}

}  // namespace

int run_cli(int argc, const char* const* argv, const Cluster* cluster) {
  const Cluster alone;
  const Cluster& c = cluster ? *cluster : alone;
  // Every rank parses the same command line and fails alike; rank 0 speaks for all.
  const bool speaks = c.root();
  try {
    const std::optional<Options> opt = [&]() -> std::optional<Options> {
      if (speaks) return parse_options(argc, argv);
      std::ostringstream quiet;  // --help and --version: printed once
      return parse_options(argc, argv, quiet);
    }();
    if (!opt) return 0;
    log::set_level(opt->quiet || !speaks ? log::Level::Quiet
                   : opt->verbose        ? log::Level::Verbose
                                         : log::Level::Normal);
    return run(*opt, c);
  } catch (const Error& e) {
    if (speaks) log::error(e.what());
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    if (speaks) log::error("out of host memory");
    return static_cast<int>(ExitCode::Device);
  } catch (const std::exception& e) {
    if (speaks) log::error(std::string("internal error: ") + e.what());
    return 70;
  }
}

}  // namespace clpt
