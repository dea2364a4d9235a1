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

// Every device of every platform; empty when there is no OpenCL platform at all.
std::vector<DeviceInfo> list_devices();

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
