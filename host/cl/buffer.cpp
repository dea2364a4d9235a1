#include "cl/buffer.h"

#include <utility>

#include "cl/cl_error.h"
#include "util/error.h"

namespace clpt::cl {
namespace {
std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }
}  // namespace

Buffer::Buffer(const Context& ctx, size_t bytes, cl_mem_flags flags, const void* data,
               const char* what)
    : ctx_(&ctx), size_(bytes) {
  const DeviceInfo& dev = ctx.device();
  if (bytes > dev.max_alloc_bytes || bytes > dev.global_mem_bytes)
    throw Error(ExitCode::Device,
                std::string("the ") + what + " needs " + mib(bytes) + ", more than the device '" +
                    dev.name + "' can allocate at once (" + mib(dev.max_alloc_bytes) +
                    "); use a smaller scene or resolution, or another device");
  const size_t alloc = bytes < 16 ? 16 : bytes;
  cl_int err = CL_SUCCESS;
  mem_ = clCreateBuffer(ctx.get(), flags, alloc, nullptr, &err);
  ctx.check(err, std::string("clCreateBuffer (") + what + ", " + mib(bytes) + ")");
  ctx.note_buffer(mem_, what, bytes);
  if (data && bytes) write(data, bytes);
}

Buffer::~Buffer() {
  if (mem_) {
    ctx_->forget_buffer(mem_);
    clReleaseMemObject(mem_);
  }
}

Buffer::Buffer(Buffer&& o) noexcept
    : mem_(std::exchange(o.mem_, nullptr)), ctx_(o.ctx_), size_(std::exchange(o.size_, 0)) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    if (mem_) {
      ctx_->forget_buffer(mem_);
      clReleaseMemObject(mem_);
    }
    mem_ = std::exchange(o.mem_, nullptr);
    ctx_ = o.ctx_;
    size_ = std::exchange(o.size_, 0);
  }
  return *this;
}

void Buffer::write(const void* data, size_t bytes, size_t offset) {
  ctx_->check(clEnqueueWriteBuffer(ctx_->queue(), mem_, CL_TRUE, offset, bytes, data, 0, nullptr,
                                   nullptr),
              "clEnqueueWriteBuffer");
}

void Buffer::read(void* data, size_t bytes, size_t offset) const {
  ctx_->check(clEnqueueReadBuffer(ctx_->queue(), mem_, CL_TRUE, offset, bytes, data, 0, nullptr,
                                  nullptr),
              "clEnqueueReadBuffer");
}

void Buffer::fill_zero() {
  const cl_uint zero = 0;
  const size_t bytes = (size_ < 16 ? 16 : size_) & ~size_t(3);
  ctx_->check(clEnqueueFillBuffer(ctx_->queue(), mem_, &zero, sizeof(zero), 0, bytes, 0, nullptr,
                                  nullptr),
              "clEnqueueFillBuffer");
}

}  // namespace clpt::cl
