#include "cl/context.h"

#include <algorithm>
#include <vector>

#include "cl/cl_error.h"
#include "util/error.h"

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
  for (const auto& [key, program] : programs_) clReleaseProgram(program);
  if (queue_) {
    clFinish(queue_);
    clReleaseCommandQueue(queue_);
  }
  if (context_) clReleaseContext(context_);
}

cl_program Context::find_program(const std::string& key) const {
  std::lock_guard<std::mutex> lock(programs_mutex_);
  const auto it = programs_.find(key);
  if (it == programs_.end()) return nullptr;
  clRetainProgram(it->second);
  return it->second;
}

void Context::keep_program(const std::string& key, cl_program program) const {
  std::lock_guard<std::mutex> lock(programs_mutex_);
  if (programs_.count(key)) return;
  clRetainProgram(program);
  programs_.emplace(key, program);
}

void Context::finish() const { check(clFinish(queue_), "clFinish"); }

namespace {
std::string bytes_text(size_t bytes) {
  if (bytes < (size_t(1) << 20)) return std::to_string((bytes + 1023) >> 10) + " KiB";
  return std::to_string((bytes + (size_t(1) << 19)) >> 20) + " MiB";
}
}  // namespace

void Context::note_launch(const std::string& kernel, size_t work_items) const {
  std::lock_guard<std::mutex> lock(notes_mutex_);
  last_kernel_ = kernel;
  last_work_items_ = work_items;
}

void Context::note_buffer(cl_mem mem, const char* what, size_t bytes) const {
  std::lock_guard<std::mutex> lock(notes_mutex_);
  buffers_[mem] = BufferNote{what ? what : "buffer", bytes};
}

void Context::forget_buffer(cl_mem mem) const {
  std::lock_guard<std::mutex> lock(notes_mutex_);
  buffers_.erase(mem);
}

std::string Context::resource_report() const {
  std::lock_guard<std::mutex> lock(notes_mutex_);
  std::string r = last_kernel_.empty() ? std::string("no kernel launched yet")
                                       : "last kernel: " + last_kernel_ + " (" +
                                             std::to_string(last_work_items_) + " work-items)";
  std::vector<const BufferNote*> notes;
  size_t total = 0;
  for (const auto& [mem, note] : buffers_) {
    notes.push_back(&note);
    total += note.bytes;
  }
  std::sort(notes.begin(), notes.end(), [](const BufferNote* a, const BufferNote* b) {
    return a->bytes != b->bytes ? a->bytes > b->bytes : a->what < b->what;
  });
  r += "; device buffers: " + bytes_text(total) + " in " + std::to_string(notes.size()) + " of " +
       bytes_text(device_.global_mem_bytes);
  for (size_t i = 0; i < notes.size() && i < 3; ++i)
    r += std::string(i ? ", " : " (largest: ") + notes[i]->what + " " + bytes_text(notes[i]->bytes);
  if (!notes.empty()) r += ")";
  return r;
}

void Context::check(cl_int code, const std::string& what) const {
  if (code == CL_SUCCESS) return;
  if (code == CL_OUT_OF_RESOURCES || code == CL_MEM_OBJECT_ALLOCATION_FAILURE ||
      code == CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST) {
    throw Error(ExitCode::Device,
                what + " failed: " + error_name(code) + " (" + std::to_string(code) +
                    ") on '" + device_.name + "': the device ran out of memory or resources; " +
                    resource_report() +
                    ". Try a smaller resolution or scene, a smaller --bdpt-memory or photon "
                    "count, or another device");
  }
  cl::check(code, what.c_str());
}

}  // namespace clpt::cl
