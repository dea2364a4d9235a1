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

  // Programs already built on this context, by the kernel cache's key (device, options,
  // resolved source): a second Program with the same key takes the first one's cl_program
  // (retained) instead of loading or building it again. Renderers made one after another
  // on one context (the Python module, the test suite's batches) build each program once.
  // find_program returns a retained program or nullptr; keep_program retains its own.
  cl_program find_program(const std::string& key) const;
  void keep_program(const std::string& key, cl_program program) const;

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
  mutable std::mutex programs_mutex_;
  mutable std::unordered_map<std::string, cl_program> programs_;
};

}  // namespace clpt::cl
