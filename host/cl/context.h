// RAII owner of an OpenCL context and in-order command queue on one device.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <mutex>
#include <string>
#include <unordered_map>

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

  // check() for calls on this context's queue: on failure throws Error(Device) naming `what`,
  // the error, and for a lack of memory or resources (which an in-order queue may report at
  // the next blocking call, not at the launch that caused it) the last kernel launched and
  // the device buffers alive: their total and the largest by name.
  void check(cl_int code, const std::string& what) const;
  // What check() adds to such an error: "last kernel: K (N work-items); device buffers: ...".
  std::string resource_report() const;

  // Bookkeeping for resource_report(): Buffer and Kernel call these.
  void note_launch(const std::string& kernel, size_t work_items) const;
  void note_buffer(cl_mem mem, const char* what, size_t bytes) const;
  void forget_buffer(cl_mem mem) const;

 private:
  struct BufferNote {
    std::string what;
    size_t bytes = 0;
  };
  DeviceInfo device_;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  mutable std::mutex notes_mutex_;
  mutable std::unordered_map<cl_mem, BufferNote> buffers_;
  mutable std::string last_kernel_;
  mutable size_t last_work_items_ = 0;
};

}  // namespace clpt::cl
