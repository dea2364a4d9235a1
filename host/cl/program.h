// Kernel sources, #include resolution, program build with an on-disk binary cache, kernels.
#pragma once

#include <CL/cl.h>

#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "cl/buffer.h"
#include "cl/context.h"
#include "cl/embedded_sources.h"
#include "util/error.h"

namespace clpt::cl {

// Where kernel files come from: embedded roots searched in order, or a directory on disk
// (CLPT_KERNEL_DIR / --kernel-dir) which then takes precedence for the files it has.
struct KernelSources {
  std::vector<const std::vector<embedded::EmbeddedFile>*> roots;
  std::filesystem::path disk_dir;  // empty: embedded only

  static KernelSources core();  // kernels/ (plus CLPT_KERNEL_DIR from the environment)
};

// Resolves #include "..." recursively (each file once) into one source string with #line
// markers naming the real files. Throws Error(Device) for a missing file.
std::string resolve_kernel_source(const std::string& entry_file, const KernelSources& sources);

// One OpenCL program: its entry file under kernels/ and the build options beyond the ones
// every program gets (build_options). A name of its own for files that hold it (the dump).
struct ProgramSpec {
  const char* name;        // e.g. "mmlt"
  const char* entry_file;  // e.g. "integrators/mlt.cl"
  const char* options;     // e.g. "-DCLPT_MLT_MULTIPLEXED=1"; "" for none
  // Options given to Intel GPUs (DeviceInfo::is_intel_gpu) as well, tried first and dropped
  // where the driver refuses them (Program's optional_options); "" for none.
  const char* intel_gpu_options = "";
};

// The options a program is built with: "-cl-std=CL1.2", then `extra`, then the environment's
// CLPT_BUILD_OPTIONS (a vendor's own options, e.g. NVIDIA's -cl-nv-verbose, which puts each
// kernel's registers and spills in the build log); they are part of the kernel cache's key.
std::string build_options(const std::string& extra);

// What a device of this kind is given on top of build_options(extra) (the kernel dump has the
// GPUs' view, none): CPU devices test a BVH leaf's triangles four at a time in float4 lanes,
// -DCLPT_TRIANGLE_LANES=4 (kernels/bvh/intersect.cl), and PoCL's devices may use clang's
// prefetch builtin, -DCLPT_PREFETCH_HINTS=1 (Oclgrind, a CPU device too, cannot run it);
// either unless `options` names the macro already.
std::string device_kind_options(const DeviceInfo& dev, const std::string& options);

// Whether the render programs for this device read the float4 lanes' positions
// (CLPT_TRIANGLE_LANES 4), as build_options and device_kind_options decide it: CPU devices,
// unless CLPT_BUILD_OPTIONS names the macro. The scene's lanes buffer is uploaded only where
// this holds (render/scene_buffers).
bool triangle_lanes(const DeviceInfo& dev);

struct BuildInfo {
  bool from_cache = false;   // loaded from the on-disk cache
  bool from_memory = false;  // the context had it already (Context::find_program)
  double seconds = 0.0;  // wall time to get a usable program (cache load or full build)
  std::string cache_file;
  std::string options;          // the options of the program in use
  std::string dropped_options;  // optional options the build refused (then left out); "" if none
};

// Where compiled binaries are cached: $CLPT_CACHE_DIR, else $XDG_CACHE_HOME/clpt,
// else ~/.cache/clpt. Returns empty when none can be determined (cache disabled).
std::filesystem::path kernel_cache_dir();

// Whether clpt's binary cache serves `dev`. Not PoCL (unless CLPT_CACHE_POCL=1): PoCL keeps its
// own kernel cache, and asking it for a program's binary (CL_PROGRAM_BINARIES) makes it
// generate every kernel's generic work-group function, which no launch then uses: bdpt's cold
// build 4.2 s with clpt's cache, 1.4 s without; a warm start costs 0.074 s from PoCL's cache
// against 0.037 s from clpt's (docs/BENCHMARKS.md, session 26).
bool binary_cache_serves(const DeviceInfo& dev);

class Program {
 public:
  // Builds entry_file (e.g. "integrators/pt.cl") for ctx's device. Options always include
  // "-cl-std=CL1.2"; never -cl-fast-relaxed-math. A failed build throws Error(Device)
  // carrying the build log. optional_options (a vendor's own, e.g. Intel's register-file
  // size) go after the others; where the build with them fails, the program is built
  // without them (BuildInfo::dropped_options), so a driver that does not know them still
  // runs clpt. Each option set has its own cache entry.
  Program(const Context& ctx, const std::string& entry_file, const std::string& options = "",
          const KernelSources& sources = KernelSources::core(),
          const std::string& optional_options = "");
  // spec's program, with spec.intel_gpu_options where ctx's device is an Intel GPU.
  Program(const Context& ctx, const ProgramSpec& spec);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  cl_program get() const { return program_; }
  const BuildInfo& build_info() const { return info_; }

 private:
  // The program for `options`: this context's, the cache's or a new build. A failed build
  // returns false with its log in *failure_log where that is given, else throws.
  bool obtain(const Context& ctx, const std::string& entry_file, const std::string& options,
              const std::string& source, std::string* failure_log);

  cl_program program_ = nullptr;
  BuildInfo info_;
};

class Kernel {
 public:
  Kernel(const Program& program, const char* name);
  ~Kernel();
  Kernel(Kernel&& other) noexcept;
  Kernel& operator=(Kernel&& other) noexcept;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  Kernel& arg(cl_uint index, const Buffer& buffer);
  template <class T>
  Kernel& arg(cl_uint index, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>, "kernel arguments must be plain data");
    set_raw(index, sizeof(T), &value);
    return *this;
  }
  // Binds args in order starting at `first`; returns the next free index.
  template <class... Args>
  cl_uint args(cl_uint first, const Args&... a) {
    (arg(first++, a), ...);
    return first;
  }

  // 1-D launch over `count` work-items. The global size is rounded up to a multiple of
  // the work-group size chosen for the device, so kernels must guard get_global_id(0) < count.
  void launch(const Context& ctx, size_t count) const;

  cl_kernel get() const { return kernel_; }
  const std::string& name() const { return name_; }

 private:
  void set_raw(cl_uint index, size_t size, const void* value);
  cl_kernel kernel_ = nullptr;
  std::string name_;
};

}  // namespace clpt::cl
