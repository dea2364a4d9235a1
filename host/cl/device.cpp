#include "cl/device.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <mutex>
#include <sstream>

#include "cl/cl_error.h"
#include "util/error.h"
#include "util/log.h"

namespace clpt::cl {
namespace {

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  size_t size = 0;
  if (clGetPlatformInfo(p, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetPlatformInfo(p, what, size, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string device_string(cl_device_id d, cl_device_info what) {
  size_t size = 0;
  if (clGetDeviceInfo(d, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetDeviceInfo(d, what, size, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

template <class T>
T device_value(cl_device_id d, cl_device_info what) {
  T v{};
  clGetDeviceInfo(d, what, sizeof(T), &v, nullptr);
  return v;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

bool DeviceInfo::is_pocl() const {
  return lower(platform_name).find("portable computing language") != std::string::npos ||
         lower(platform_vendor).find("pocl") != std::string::npos;
}

bool DeviceInfo::is_intel_gpu() const {
  return is_gpu() && lower(platform_vendor).find("intel") != std::string::npos;
}

std::string DeviceInfo::label() const {
  std::ostringstream s;
  s << platform_index << ":" << device_index << " " << name << " (" << platform_name << ")";
  return s.str();
}

void apply_runtime_settings() {
  // Once a process: setenv must not race the runtime's own getenv on its worker threads.
  static std::once_flag once;
  std::call_once(once, [] {
    const char* method = std::getenv("POCL_WORK_GROUP_METHOD");
    if (method == nullptr || *method == '\0') {
      ::setenv("POCL_WORK_GROUP_METHOD", "loops", 1);
      log::verbose("PoCL work-group method: loops (set POCL_WORK_GROUP_METHOD to choose another)");
    } else {
      log::verbose(std::string("PoCL work-group method: ") + method + " (POCL_WORK_GROUP_METHOD)");
    }
  });
}

std::vector<DeviceInfo> list_devices() {
  apply_runtime_settings();
  std::vector<DeviceInfo> out;
  cl_uint num_platforms = 0;
  if (clGetPlatformIDs(0, nullptr, &num_platforms) != CL_SUCCESS || num_platforms == 0) return out;
  std::vector<cl_platform_id> platforms(num_platforms);
  clGetPlatformIDs(num_platforms, platforms.data(), nullptr);
  for (cl_uint pi = 0; pi < num_platforms; ++pi) {
    cl_uint num_devices = 0;
    if (clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, 0, nullptr, &num_devices) != CL_SUCCESS)
      continue;
    std::vector<cl_device_id> devices(num_devices);
    clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, num_devices, devices.data(), nullptr);
    for (cl_uint di = 0; di < num_devices; ++di) {
      DeviceInfo d;
      d.platform = platforms[pi];
      d.id = devices[di];
      d.platform_index = pi;
      d.device_index = di;
      d.platform_name = platform_string(platforms[pi], CL_PLATFORM_NAME);
      d.platform_vendor = platform_string(platforms[pi], CL_PLATFORM_VENDOR);
      d.name = device_string(devices[di], CL_DEVICE_NAME);
      d.version = device_string(devices[di], CL_DEVICE_VERSION);
      d.driver_version = device_string(devices[di], CL_DRIVER_VERSION);
      d.c_version = device_string(devices[di], CL_DEVICE_OPENCL_C_VERSION);
      d.type = device_value<cl_device_type>(devices[di], CL_DEVICE_TYPE);
      d.max_work_group_size = device_value<size_t>(devices[di], CL_DEVICE_MAX_WORK_GROUP_SIZE);
      d.global_mem_bytes = device_value<cl_ulong>(devices[di], CL_DEVICE_GLOBAL_MEM_SIZE);
      d.max_alloc_bytes = device_value<cl_ulong>(devices[di], CL_DEVICE_MAX_MEM_ALLOC_SIZE);
      d.compute_units = device_value<cl_uint>(devices[di], CL_DEVICE_MAX_COMPUTE_UNITS);
      out.push_back(d);
    }
  }
  return out;
}

std::string describe_devices(const std::vector<DeviceInfo>& devices) {
  if (devices.empty())
    return "  (no OpenCL devices found; is an ICD installed? On Debian: "
           "apt-get install pocl-opencl-icd)\n";
  std::ostringstream s;
  for (const DeviceInfo& d : devices) {
    const char* kind = d.is_gpu() ? "GPU" : (d.type & CL_DEVICE_TYPE_CPU) ? "CPU" : "other";
    s << "  " << d.platform_index << ":" << d.device_index << "  [" << kind << "] " << d.name
      << "\n        platform: " << d.platform_name << ", " << d.version
      << ", driver " << d.driver_version << ", " << d.compute_units << " compute units, "
      << (d.global_mem_bytes >> 20) << " MiB\n";
  }
  return s.str();
}

DeviceInfo select_device(const std::string& spec_in) {
  const std::vector<DeviceInfo> devices = list_devices();
  const std::string spec = lower(spec_in);
  auto fail = [&](const std::string& why) -> DeviceInfo {
    throw Error(ExitCode::Device, why + "\nOpenCL devices found:\n" + describe_devices(devices));
  };
  if (devices.empty()) return fail("no OpenCL device found");

  auto first = [&](auto&& pred) -> const DeviceInfo* {
    for (const DeviceInfo& d : devices)
      if (pred(d)) return &d;
    return nullptr;
  };
  const DeviceInfo* found = nullptr;
  if (spec.empty()) {
    found = first([](const DeviceInfo& d) { return d.is_gpu(); });
    if (!found) found = first([](const DeviceInfo& d) { return d.is_pocl(); });
    if (!found) found = &devices.front();
  } else if (spec == "gpu") {
    found = first([](const DeviceInfo& d) { return d.is_gpu(); });
    if (!found) return fail("--device=gpu: no GPU device found");
  } else if (spec == "cpu") {
    found = first([](const DeviceInfo& d) { return (d.type & CL_DEVICE_TYPE_CPU) != 0; });
    if (!found) return fail("--device=cpu: no CPU device found");
  } else if (spec == "pocl") {
    found = first([](const DeviceInfo& d) { return d.is_pocl(); });
    if (!found) return fail("--device=pocl: the PoCL platform is not installed "
                            "(apt-get install pocl-opencl-icd)");
  } else if (auto colon = spec.find(':');
             colon != std::string::npos && colon > 0 &&
             spec.find_first_not_of("0123456789:") == std::string::npos) {
    const unsigned long p = std::stoul(spec.substr(0, colon));
    const std::string rest = spec.substr(colon + 1);
    if (rest.empty() || rest.find(':') != std::string::npos)
      return fail("--device=" + spec_in + ": expected PLATFORM:DEVICE indices");
    const unsigned long d = std::stoul(rest);
    found = first([&](const DeviceInfo& x) {
      return x.platform_index == p && x.device_index == d;
    });
    if (!found) return fail("--device=" + spec_in + ": no such platform:device");
  } else {
    found = first([&](const DeviceInfo& d) {
      return lower(d.name).find(spec) != std::string::npos ||
             lower(d.platform_name).find(spec) != std::string::npos;
    });
    if (!found) return fail("--device=" + spec_in + ": no device name matches");
  }
  return *found;
}

namespace {

int local_rank() {
  // Open MPI's mpirun, Slurm's srun, MPICH's Hydra; -1 when no launcher set one.
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_RANK", "SLURM_LOCALID", "MPI_LOCALRANKID"})
    if (const char* value = std::getenv(v)) {
      char* end = nullptr;
      const long r = std::strtol(value, &end, 10);
      if (end != value && *end == '\0' && r >= 0 && r < (1L << 20)) return static_cast<int>(r);
    }
  return -1;
}

// Every GPU, or without one every device (--device all and rank); throws when there is none.
std::vector<DeviceInfo> gpus_else_every_device(const std::string& spec) {
  const std::vector<DeviceInfo> devices = list_devices();
  std::vector<DeviceInfo> chosen;
  for (const DeviceInfo& d : devices)
    if (d.is_gpu()) chosen.push_back(d);
  if (chosen.empty()) chosen = devices;
  if (chosen.empty())
    throw Error(ExitCode::Device, "--device=" + spec + ": no OpenCL device found\nOpenCL devices found:\n" +
                                      describe_devices(devices));
  return chosen;
}

}  // namespace

std::vector<DeviceInfo> select_devices(const std::string& spec) {
  if (lower(spec) == "rank") {
    const int r = local_rank();
    if (r < 0)
      throw Error(ExitCode::Usage, "--device=rank: no MPI launcher set a local rank "
                                   "(OMPI_COMM_WORLD_LOCAL_RANK, SLURM_LOCALID or MPI_LOCALRANKID)");
    const std::vector<DeviceInfo> chosen = gpus_else_every_device("rank");
    return {chosen[size_t(r) % chosen.size()]};
  }
  if (lower(spec) == "all") return gpus_else_every_device("all");
  std::vector<DeviceInfo> chosen;
  size_t start = 0;
  while (true) {
    const size_t comma = spec.find(',', start);
    const std::string one = spec.substr(start, comma == std::string::npos ? std::string::npos
                                                                           : comma - start);
    if (one.empty() && spec.find(',') != std::string::npos)
      throw Error(ExitCode::Usage, "--device=" + spec + ": an empty entry in the list");
    const DeviceInfo d = select_device(one);
    for (const DeviceInfo& c : chosen)
      if (c.id == d.id)
        throw Error(ExitCode::Usage, "--device=" + spec + ": " + d.label() +
                                         " is named twice (each device renders once)");
    chosen.push_back(d);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return chosen;
}

}  // namespace clpt::cl
