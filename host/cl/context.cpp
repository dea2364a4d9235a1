#include "cl/context.h"

#include "cl/cl_error.h"

namespace clpt::cl {

Context::Context(const DeviceInfo& device) : device_(device) {
  cl_int err = CL_SUCCESS;
  const cl_context_properties props[] = {
      CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(device.platform), 0};
  context_ = clCreateContext(props, 1, &device.id, nullptr, nullptr, &err);
  check(err, "clCreateContext");
  // clCreateCommandQueue is deprecated in 2.0 but is the OpenCL 1.2 baseline we target.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
  queue_ = clCreateCommandQueue(context_, device.id, 0, &err);
#pragma GCC diagnostic pop
  if (err != CL_SUCCESS) {
    clReleaseContext(context_);
    check(err, "clCreateCommandQueue");
  }
}

Context::~Context() {
  if (queue_) {
    clFinish(queue_);
    clReleaseCommandQueue(queue_);
  }
  if (context_) clReleaseContext(context_);
}

void Context::finish() const { check(clFinish(queue_), "clFinish"); }

}  // namespace clpt::cl
