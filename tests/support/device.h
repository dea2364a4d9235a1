// Shared fixtures for tests that run kernels on the PoCL device.
#pragma once

#include "cl/context.h"
#include "cl/program.h"

#include <string>

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

// The test program built from `file` (e.g. "kernels/bsdf_test.cl") with test_kernel_sources(),
// built once per process and kept; `options` adds build options (a program of its own).
const cl::Program& test_program(const std::string& file, const std::string& options = "");

}  // namespace clpt::test
