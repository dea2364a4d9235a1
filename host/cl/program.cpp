#include "cl/program.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <utility>

#include "cl/cl_error.h"
#include "util/atomic_file.h"
#include "util/hash.h"
#include "util/log.h"

namespace clpt::cl {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Sources and #include resolution

KernelSources KernelSources::core() {
  KernelSources s;
  s.roots.push_back(&embedded::core());
  if (const char* dir = std::getenv("CLPT_KERNEL_DIR"); dir && *dir) s.disk_dir = dir;
  return s;
}

namespace {

// Finds `path` (already normalised, '/'-separated, relative) in the sources.
bool find_source(const std::string& path, const KernelSources& sources, std::string* out) {
  if (!sources.disk_dir.empty()) {
    std::ifstream f(sources.disk_dir / path, std::ios::binary);
    if (f) {
      std::ostringstream ss;
      ss << f.rdbuf();
      *out = ss.str();
      return true;
    }
  }
  for (const auto* root : sources.roots)
    for (const embedded::EmbeddedFile& file : *root)
      if (path == file.path) {
        out->assign(file.contents);
        return true;
      }
  return false;
}

std::string parent_dir(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string normalise(const std::string& path) {
  return fs::path(path).lexically_normal().generic_string();
}

// Returns the quoted target of an `#include "..."` line, or empty.
std::string include_target(const std::string& line) {
  size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#') return {};
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, 7, "include") != 0) return {};
  const size_t open = line.find('"', i + 7);
  if (open == std::string::npos) return {};
  const size_t close = line.find('"', open + 1);
  if (close == std::string::npos) return {};
  return line.substr(open + 1, close - open - 1);
}

void resolve_into(const std::string& path, const std::string& text, const KernelSources& sources,
                  std::set<std::string>& seen, std::ostringstream& out, int depth) {
  if (depth > 64) throw Error(ExitCode::Device, "kernel #include nesting too deep at " + path);
  out << "#line 1 \"" << path << "\"\n";
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string target = include_target(line);
    if (target.empty()) {
      out << line << '\n';
      continue;
    }
    // Relative to the including file first, then to the roots.
    std::string resolved, contents;
    for (const std::string& candidate : {normalise(parent_dir(path) + target), normalise(target)})
      if (find_source(candidate, sources, &contents)) {
        resolved = candidate;
        break;
      }
    if (resolved.empty())
      throw Error(ExitCode::Device, path + ":" + std::to_string(line_no) +
                                        ": kernel include file not found: \"" + target + "\"");
    if (seen.insert(resolved).second) {
      resolve_into(resolved, contents, sources, seen, out, depth + 1);
    }
    out << "#line " << line_no + 1 << " \"" << path << "\"\n";
  }
}

}  // namespace

std::string resolve_kernel_source(const std::string& entry_file, const KernelSources& sources) {
  std::string text;
  const std::string entry = normalise(entry_file);
  if (!find_source(entry, sources, &text))
    throw Error(ExitCode::Device, "kernel source not found: " + entry);
  std::set<std::string> seen{entry};
  std::ostringstream out;
  resolve_into(entry, text, sources, seen, out, 0);
  return out.str();
}

// ---------------------------------------------------------------------------------------
// Binary cache

fs::path kernel_cache_dir() {
  if (const char* d = std::getenv("CLPT_CACHE_DIR"); d && *d) return fs::path(d);
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "clpt";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "clpt";
  return {};
}

bool binary_cache_serves(const DeviceInfo& dev) {
  if (!dev.is_pocl()) return true;
  const char* forced = std::getenv("CLPT_CACHE_POCL");
  return forced && std::string(forced) == "1";
}

namespace {

constexpr char kCacheMagic[8] = {'C', 'L', 'P', 'T', 'K', 'C', '0', '1'};

struct CacheKey {
  std::string text;  // everything the binary depends on
  std::string file_name;
  uint64_t check = 0;  // second, independent hash of the key, stored in the entry
};

CacheKey make_key(const DeviceInfo& dev, const std::string& options, const std::string& source) {
  CacheKey k;
  std::ostringstream s;
  s << "clpt-kernel-cache-v1\n"
    << dev.platform_vendor << '\n'
    << dev.platform_name << '\n'
    << dev.name << '\n'
    << dev.version << '\n'
    << dev.driver_version << '\n'
    << options << '\n'
    << source;
  k.text = s.str();
  const Hash128 h = hash128(k.text.data(), k.text.size());
  std::ostringstream name;
  name << std::hex << std::setfill('0') << std::setw(16) << h.high << std::setw(16) << h.low << ".clbin";
  k.file_name = name.str();
  k.check = hash64(k.text.data(), k.text.size(), 0);
  return k;
}

bool read_cache(const fs::path& file, uint64_t key_check, std::vector<unsigned char>* binary) {
  std::ifstream f(file, std::ios::binary);
  if (!f) return false;
  char magic[8];
  uint64_t check = 0, size = 0, payload_hash = 0;
  if (!f.read(magic, 8) || std::memcmp(magic, kCacheMagic, 8) != 0) return false;
  if (!f.read(reinterpret_cast<char*>(&check), 8) || check != key_check) return false;
  if (!f.read(reinterpret_cast<char*>(&size), 8) || size == 0 || size > (1ull << 30)) return false;
  if (!f.read(reinterpret_cast<char*>(&payload_hash), 8)) return false;
  binary->resize(size);
  if (!f.read(reinterpret_cast<char*>(binary->data()), static_cast<std::streamsize>(size)))
    return false;
  return hash64(binary->data(), binary->size(), 0) == payload_hash;
}

void write_cache(const fs::path& file, uint64_t key_check, const std::vector<unsigned char>& bin) {
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  // Atomic: readers see the old entry or the whole new one; a cache that cannot be written only
  // costs the next start its build.
  std::string why;
  const bool written = write_file_atomically(file, [&](std::ostream& f) {
    const uint64_t size = bin.size();
    const uint64_t payload_hash = hash64(bin.data(), bin.size(), 0);
    f.write(kCacheMagic, 8);
    f.write(reinterpret_cast<const char*>(&key_check), 8);
    f.write(reinterpret_cast<const char*>(&size), 8);
    f.write(reinterpret_cast<const char*>(&payload_hash), 8);
    f.write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(size));
  }, &why);
  if (!written)
    log::verbose("kernel cache: cannot write " + file.string() + (why.empty() ? "" : ": " + why));
}

std::string build_log(cl_program program, cl_device_id device) {
  size_t size = 0;
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
  std::string log(size, '\0');
  if (size) clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log;
}

std::vector<unsigned char> program_binary(cl_program program) {
  size_t size = 0;
  if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof(size), &size, nullptr) !=
          CL_SUCCESS ||
      size == 0)
    return {};
  std::vector<unsigned char> bin(size);
  unsigned char* ptr = bin.data();
  if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof(ptr), &ptr, nullptr) != CL_SUCCESS)
    return {};
  return bin;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Program

std::string build_options(const std::string& extra) {
  std::string options = "-cl-std=CL1.2" + (extra.empty() ? "" : " " + extra);
  if (const char* user = std::getenv("CLPT_BUILD_OPTIONS"); user && *user) options += std::string(" ") + user;
  return options;
}

std::string device_kind_options(const DeviceInfo& dev, const std::string& options) {
  std::string kind;
  if (dev.is_cpu() && options.find("CLPT_TRIANGLE_LANES") == std::string::npos)
    kind += " -DCLPT_TRIANGLE_LANES=4";
  if (dev.is_pocl() && options.find("CLPT_PREFETCH_HINTS") == std::string::npos)
    kind += " -DCLPT_PREFETCH_HINTS=1";
  return kind;
}

bool triangle_lanes(const DeviceInfo& dev) {
  const std::string options = build_options("");
  return (options + device_kind_options(dev, options)).find("-DCLPT_TRIANGLE_LANES=4") !=
         std::string::npos;
}

Program::Program(const Context& ctx, const std::string& entry_file, const std::string& extra_options,
                 const KernelSources& sources, const std::string& optional_options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string options = build_options(extra_options);
  options += device_kind_options(ctx.device(), options);
  const std::string source = resolve_kernel_source(entry_file, sources);
  if (!optional_options.empty()) {
    std::string log;
    if (!obtain(ctx, entry_file, options + " " + optional_options, source, &log)) {
      info_.dropped_options = optional_options;
      log::verbose("kernel program " + entry_file + ": the build with '" + optional_options +
                   "' failed; building without them. Build log:\n" + log);
    }
  }
  if (!program_) obtain(ctx, entry_file, options, source, nullptr);
  info_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::verbose("kernel program " + entry_file + " (options '" + info_.options + "'): " +
               (info_.from_memory ? "this context's" : info_.from_cache ? "loaded from cache" : "built") +
               " in " + std::to_string(info_.seconds) + " s");
}

Program::Program(const Context& ctx, const ProgramSpec& spec)
    : Program(ctx, spec.entry_file, spec.options, KernelSources::core(),
              ctx.device().is_intel_gpu() ? spec.intel_gpu_options : "") {}

bool Program::obtain(const Context& ctx, const std::string& entry_file, const std::string& options,
                     const std::string& source, std::string* failure_log) {
  const DeviceInfo& dev = ctx.device();
  const CacheKey key = make_key(dev, options, source);
  const fs::path cache_dir = binary_cache_serves(dev) ? kernel_cache_dir() : fs::path();
  const fs::path cache_file = cache_dir.empty() ? fs::path() : cache_dir / key.file_name;
  info_.cache_file = cache_file.string();
  info_.options = options;

  // 0. This context's own programs: built or loaded before in this process.
  if ((program_ = ctx.find_program(key.file_name))) {
    info_.from_memory = true;
    return true;
  }

  // 1. The cache, when an entry exists and the driver accepts it.
  std::vector<unsigned char> binary;
  if (!cache_file.empty() && read_cache(cache_file, key.check, &binary)) {
    const unsigned char* ptr = binary.data();
    const size_t size = binary.size();
    cl_int status = CL_SUCCESS, err = CL_SUCCESS;
    cl_program p = clCreateProgramWithBinary(ctx.get(), 1, &dev.id, &size, &ptr, &status, &err);
    if (err == CL_SUCCESS && status == CL_SUCCESS &&
        clBuildProgram(p, 1, &dev.id, options.c_str(), nullptr, nullptr) == CL_SUCCESS) {
      program_ = p;
      info_.from_cache = true;
    } else {
      if (p) clReleaseProgram(p);
      log::verbose("kernel cache: entry " + cache_file.string() + " rejected; rebuilding");
    }
  }

  // 2. A full build from source.
  if (!program_) {
    const char* text = source.c_str();
    const size_t length = source.size();
    cl_int err = CL_SUCCESS;
    program_ = clCreateProgramWithSource(ctx.get(), 1, &text, &length, &err);
    check(err, "clCreateProgramWithSource");
    const cl_int build = clBuildProgram(program_, 1, &dev.id, options.c_str(), nullptr, nullptr);
    const std::string log = build_log(program_, dev.id);
    if (build != CL_SUCCESS) {
      clReleaseProgram(program_);
      program_ = nullptr;
      if (failure_log) {
        *failure_log = log;
        return false;
      }
      throw Error(ExitCode::Device, "building kernel program " + entry_file + " for '" + dev.name +
                                        "' failed (" + error_name(build) + ") with options '" +
                                        options + "'. Build log:\n" + log);
    }
    if (!log.empty()) log::verbose("build log for " + entry_file + ":\n" + log);
    if (!cache_file.empty()) {
      const std::vector<unsigned char> bin = program_binary(program_);
      if (!bin.empty()) write_cache(cache_file, key.check, bin);
    }
  }
  ctx.keep_program(key.file_name, program_);
  return true;
}

Program::~Program() {
  if (program_) clReleaseProgram(program_);
}

// ---------------------------------------------------------------------------------------
// Kernel

Kernel::Kernel(const Program& program, const char* name) : name_(name) {
  cl_int err = CL_SUCCESS;
  kernel_ = clCreateKernel(program.get(), name, &err);
  check(err, (std::string("clCreateKernel(") + name + ")").c_str());
}

Kernel::~Kernel() {
  if (kernel_) clReleaseKernel(kernel_);
}

Kernel::Kernel(Kernel&& o) noexcept
    : kernel_(std::exchange(o.kernel_, nullptr)), name_(std::move(o.name_)) {}

Kernel& Kernel::operator=(Kernel&& o) noexcept {
  if (this != &o) {
    if (kernel_) clReleaseKernel(kernel_);
    kernel_ = std::exchange(o.kernel_, nullptr);
    name_ = std::move(o.name_);
  }
  return *this;
}

Kernel& Kernel::arg(cl_uint index, const Buffer& buffer) {
  cl_mem mem = buffer.get();
  set_raw(index, sizeof(cl_mem), &mem);
  return *this;
}

void Kernel::set_raw(cl_uint index, size_t size, const void* value) {
  const cl_int err = clSetKernelArg(kernel_, index, size, value);
  if (err != CL_SUCCESS)
    check(err, ("clSetKernelArg(" + name_ + ", " + std::to_string(index) + ")").c_str());
}

void Kernel::launch(const Context& ctx, size_t count) const {
  if (count == 0) return;
  size_t max_wg = 0, multiple = 0;
  check(clGetKernelWorkGroupInfo(kernel_, ctx.device().id, CL_KERNEL_WORK_GROUP_SIZE,
                                 sizeof(max_wg), &max_wg, nullptr),
        "clGetKernelWorkGroupInfo");
  check(clGetKernelWorkGroupInfo(kernel_, ctx.device().id,
                                 CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE, sizeof(multiple),
                                 &multiple, nullptr),
        "clGetKernelWorkGroupInfo");
  // 64 work-items (a multiple of the device's preferred multiple) unless the kernel allows
  // fewer; CLPT_WORK_GROUP_SIZE overrides it for tuning.
  if (multiple == 0) multiple = 1;
  size_t local = multiple;
  while (local < 64 && local * 2 <= max_wg) local *= 2;
  static const size_t forced = [] {
    const char* v = std::getenv("CLPT_WORK_GROUP_SIZE");
    return v ? std::strtoul(v, nullptr, 10) : 0ul;
  }();
  if (forced) local = forced;
  if (local > max_wg) local = max_wg ? max_wg : 1;
  const size_t global = (count + local - 1) / local * local;
  ctx.note_launch(name_, global);
  ctx.check(clEnqueueNDRangeKernel(ctx.queue(), kernel_, 1, nullptr, &global, &local, 0, nullptr,
                                   nullptr),
            "clEnqueueNDRangeKernel(" + name_ + ")");
}

}  // namespace clpt::cl
