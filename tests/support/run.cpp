#include "support/run.h"

#include <gtest/gtest.h>

#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#include <chrono>
#include <thread>

namespace clpt::test {

std::string read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

RunResult run_clpt(const std::vector<std::string>& args, const std::string& interrupt_after,
                   double delay) {
  RunOptions options;
  options.interrupt_after = interrupt_after;
  options.delay = delay;
  return run_program(CLPT_BINARY, args, options);
}

RunResult run_program(const std::string& binary, const std::vector<std::string>& args,
                      const RunOptions& options) {
  const std::string& interrupt_after = options.interrupt_after;
  const double delay = options.delay;
  const std::string base = "/tmp/clpt-run-" + std::to_string(::getpid()) + "-" +
                           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  const std::string out_path = base + ".out", err_path = base + ".err";
  // Everything the child needs is built before fork(): the test process runs PoCL's threads,
  // so the child may only make async-signal-safe calls (open, dup2, execve), not setenv.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) {
    const std::string kv = *e;
    const std::string name = kv.substr(0, kv.find('='));
    bool overridden = false;
    for (const auto& [k, v] : options.env) overridden |= k == name;
    if (!overridden) env_strings.push_back(kv);
  }
  for (const auto& [k, v] : options.env) env_strings.push_back(k + "=" + v);
  std::vector<char*> envp, argv;
  for (std::string& kv : env_strings) envp.push_back(kv.data());
  envp.push_back(nullptr);
  argv.push_back(const_cast<char*>(binary.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = ::open("/dev/null", O_RDONLY);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::dup2(in, 0);
    ::execve(binary.c_str(), argv.data(), envp.data());
    ::_exit(127);
  }
  RunResult r;
  if (pid < 0) return r;
  int status = 0;
  bool exited = false;
  struct rusage usage {};
  if (!interrupt_after.empty()) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(300);
    while (std::chrono::steady_clock::now() < give_up) {
      if (::wait4(pid, &status, WNOHANG, &usage) == pid) {
        exited = true;
        break;
      }
      if (read_file(err_path).find(interrupt_after) != std::string::npos) {
        std::this_thread::sleep_for(std::chrono::duration<double>(delay));
        for (int i = 0; i < options.interrupts; ++i) {
          if (i > 0) std::this_thread::sleep_for(std::chrono::duration<double>(options.interval));
          ::kill(pid, SIGINT);
        }
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  if (!exited) ::wait4(pid, &status, 0, &usage);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.max_rss_kib = usage.ru_maxrss;
  r.out = read_file(out_path);
  r.err = read_file(err_path);
  ::unlink(out_path.c_str());
  ::unlink(err_path.c_str());
  return r;
}

nlohmann::json run_clpt_stats(const std::filesystem::path& dir, const std::string& name,
                              const std::string& scene, const std::vector<std::string>& args) {
  std::vector<std::string> all = {scene, "--device", "pocl", "-q", "-o",
                                  (dir / (name + ".exr")).string(), "--stats",
                                  (dir / (name + ".json")).string()};
  all.insert(all.end(), args.begin(), args.end());
  const RunResult r = run_clpt(all);
  EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
  if (r.exit_code != 0) return nullptr;
  return nlohmann::json::parse(read_file((dir / (name + ".json")).string()));
}

}  // namespace clpt::test
