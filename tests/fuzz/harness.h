// What the libFuzzer targets share: a private scratch folder for the files an input becomes,
// removed at exit, and how a target reports a broken contract.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace clpt::fuzz {

// The target's scratch folder (made by make_scratch_dir in LLVMFuzzerInitialize).
inline std::filesystem::path& scratch_dir() {
  static std::filesystem::path dir;
  return dir;
}

// Makes a fresh folder under TMPDIR named after the target, removed at exit.
inline void make_scratch_dir(const char* target) {
  std::string templ = (std::filesystem::temp_directory_path() / ("clpt-" + std::string(target) + "-XXXXXX")).string();
  if (!::mkdtemp(templ.data())) {
    std::perror("mkdtemp");
    std::abort();
  }
  scratch_dir() = templ;
  std::atexit([] {
    std::error_code ec;
    std::filesystem::remove_all(scratch_dir(), ec);
  });
}

inline void write_file(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror(path.c_str());
    std::abort();  // the harness itself is broken, not the code under test
  }
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
}

// A broken contract: printed, then abort() so that libFuzzer keeps the input as a crash.
[[noreturn]] inline void finding(const char* target, const char* what) {
  std::fprintf(stderr, "%s: %s\n", target, what);
  std::abort();
}

}  // namespace clpt::fuzz
