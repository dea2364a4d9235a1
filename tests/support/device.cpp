#include "support/device.h"

#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>

namespace clpt::test {

cl::Context& device_context() {
  static std::unique_ptr<cl::Context> ctx = [] {
    const char* spec = std::getenv("CLPT_TEST_DEVICE");
    return std::make_unique<cl::Context>(cl::select_device(spec && *spec ? spec : "pocl"));
  }();
  return *ctx;
}

cl::KernelSources test_kernel_sources() {
  cl::KernelSources s = cl::KernelSources::core();
  s.roots.insert(s.roots.begin(), &embedded::tests());
  return s;
}

const cl::Program& test_program(const std::string& file, const std::string& options) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<cl::Program>> programs;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& program = programs[file + '\n' + options];
  if (!program)
    program = std::make_unique<cl::Program>(device_context(), file, options, test_kernel_sources());
  return *program;
}

}  // namespace clpt::test
