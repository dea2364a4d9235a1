// Kernel sources compiled into the binary (see cmake/EmbedKernels.cmake).
#pragma once

#include <string_view>
#include <vector>

namespace clpt::embedded {

struct EmbeddedFile {
  const char* path;           // relative to its root, e.g. "integrators/pt.cl"
  std::string_view contents;
};

const std::vector<EmbeddedFile>& core();  // kernels/
}  // namespace clpt::embedded
