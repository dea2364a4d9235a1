// Discovering OpenCL devices and choosing one from the --device option.
#pragma once

#include <CL/cl.h>

#include <cstdint>
#include <string>
#include <vector>

namespace clpt::cl {

struct DeviceInfo {
  cl_platform_id platform = nullptr;
  cl_device_id id = nullptr;
  unsigned platform_index = 0, device_index = 0;
  std::string platform_name, platform_vendor, name, version, driver_version, c_version;
  cl_device_type type = 0;
  size_t max_work_group_size = 1;
  uint64_t global_mem_bytes = 0, max_alloc_bytes = 0;
  unsigned compute_units = 0;

  bool is_gpu() const { return (type & CL_DEVICE_TYPE_GPU) != 0; }
  bool is_cpu() const { return (type & CL_DEVICE_TYPE_CPU) != 0; }
  bool is_pocl() const;
  bool is_intel_gpu() const;  // a GPU of Intel's own OpenCL platform (its compiler: IGC)
  std::string label() const;  // "P:D name (platform)"
};

// Every device of every platform; empty when there is no OpenCL platform at all. Applies
// apply_runtime_settings() first.
std::vector<DeviceInfo> list_devices();

// The OpenCL runtimes' settings clpt chooses, set in the process environment before the first
// OpenCL call, each only where the user has not set it:
// - POCL_WORK_GROUP_METHOD=loops: PoCL turns each kernel into a loop over a work-group's
//   work-items; its default, loopvec, prepares that loop for LLVM's loop vectorizer, which
//   clpt's kernels (one path a work-item, in loops that diverge; float4 lanes within one) only
//   pay for: loops renders the Cornell box with pt at 1.03 to 1.05 times the paths per second,
//   the 1 M-triangle spheres at 1.05 to 1.06 (docs/BENCHMARKS.md, session 45). PoCL reads it
//   when it compiles a process's first kernel, and keys its kernel cache by it.
// Safe to call more than once; list_devices calls it.
void apply_runtime_settings();

// spec: "" (first GPU, else PoCL, else the first device), "gpu", "cpu", "pocl",
// "P:D" (platform and device index), or a case-insensitive substring of the device or
// platform name. Throws Error(ExitCode::Device) listing what was found when nothing matches.
DeviceInfo select_device(const std::string& spec);

// One or several devices: "all" (every GPU; without a GPU, every device), "rank" (under an MPI
// launcher, the GPU — else the device — numbered by this process's rank on its node, modulo
// their count: one GPU per rank), or a comma-separated list of select_device specs ("0:0,0:1";
// a name substring holding a comma cannot be listed).
// Throws Error(ExitCode::Device) as select_device does, and Error(ExitCode::Usage) for a device
// named twice.
std::vector<DeviceInfo> select_devices(const std::string& spec);

// A human-readable table of devices for --list-devices and error messages.
std::string describe_devices(const std::vector<DeviceInfo>& devices);

}  // namespace clpt::cl
