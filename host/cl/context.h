// RAII owner of an OpenCL context and in-order command queue on one device.
#pragma once

#include <CL/cl.h>

#include "cl/device.h"

namespace clpt::cl {

class Context {
 public:
  explicit Context(const DeviceInfo& device);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& device() const { return device_; }
  cl_context get() const { return context_; }
  cl_command_queue queue() const { return queue_; }
  void finish() const;

 private:
  DeviceInfo device_;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
};

}  // namespace clpt::cl
