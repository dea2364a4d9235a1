#include "support/device.h"

#include <cstdlib>
#include <memory>

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

}  // namespace clpt::test
