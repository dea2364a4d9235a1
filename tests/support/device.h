// Shared fixtures for tests that run kernels on the PoCL device.
#pragma once

#include "cl/context.h"
#include "cl/program.h"

namespace clpt::embedded {
const std::vector<EmbeddedFile>& tests();  // tests/kernels, embedded into clpt_tests
}

namespace clpt::test {

// One context per test process on the PoCL CPU device (CLPT_TEST_DEVICE overrides the
// --device spec). Tests that need a device call this; it throws if none can be found.
cl::Context& device_context();

// Kernel sources for test programs: tests/kernels/ first, then the renderer's kernels/.
// Test kernels #include library code as "bvh/intersect.cl" etc. and live under "kernels/...".
cl::KernelSources test_kernel_sources();

}  // namespace clpt::test
