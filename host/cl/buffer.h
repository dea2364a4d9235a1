// RAII device buffer with blocking reads and writes.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <string>
#include <vector>

#include "cl/context.h"

namespace clpt::cl {

class Buffer {
 public:
  Buffer() = default;
  // A buffer of `bytes` (at least 16 are allocated, so empty scenes still bind), initialised
  // from `data` when given. `what` names it in errors. Fails with Error(Device) before
  // allocating when bytes exceed the device's max allocation.
  Buffer(const Context& ctx, size_t bytes, cl_mem_flags flags = CL_MEM_READ_WRITE,
         const void* data = nullptr, const char* what = "buffer");
  template <class T>
  static Buffer from_vector(const Context& ctx, const std::vector<T>& v,
                            cl_mem_flags flags = CL_MEM_READ_ONLY, const char* what = "buffer") {
    return Buffer(ctx, v.size() * sizeof(T), flags, v.empty() ? nullptr : v.data(), what);
  }
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void write(const void* data, size_t bytes, size_t offset = 0);
  void read(void* data, size_t bytes, size_t offset = 0) const;
  void fill_zero();
  template <class T>
  std::vector<T> read_vector(size_t count) const {
    std::vector<T> v(count);
    if (count) read(v.data(), count * sizeof(T));
    return v;
  }

  cl_mem get() const { return mem_; }
  size_t size() const { return size_; }  // the size asked for

 private:
  cl_mem mem_ = nullptr;
  const Context* ctx_ = nullptr;  // errors name the context's last kernel and buffers
  size_t size_ = 0;
};

}  // namespace clpt::cl
