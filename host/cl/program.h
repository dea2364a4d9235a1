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
};

// The options a program is built with: "-cl-std=CL1.2", then `extra`, then the environment's
// CLPT_BUILD_OPTIONS (a vendor's own options, e.g. NVIDIA's -cl-nv-verbose, which puts each
// kernel's registers and spills in the build log); they are part of the kernel cache's key.
std::string build_options(const std::string& extra);

struct BuildInfo {
  bool from_cache = false;   // loaded from the on-disk cache
  bool from_memory = false;  // the context had it already (Context::find_program)
  double seconds = 0.0;  // wall time to get a usable program (cache load or full build)
  std::string cache_file;
};

// Where compiled binaries are cached: $CLPT_CACHE_DIR, else $XDG_CACHE_HOME/clpt,
// else ~/.cache/clpt. Returns empty when none can be determined (cache disabled).
std::filesystem::path kernel_cache_dir();

class Program {
 public:
  // Builds entry_file (e.g. "integrators/pt.cl") for ctx's device. Options always include
  // "-cl-std=CL1.2"; never -cl-fast-relaxed-math. A failed build throws Error(Device)
  // carrying the build log.
  Program(const Context& ctx, const std::string& entry_file, const std::string& options = "",
          const KernelSources& sources = KernelSources::core());
  Program(const Context& ctx, const ProgramSpec& spec)
      : Program(ctx, spec.entry_file, spec.options) {}
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  cl_program get() const { return program_; }
  const BuildInfo& build_info() const { return info_; }

 private:
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
