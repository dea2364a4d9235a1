// Limits that keep a hostile scene file from taking unbounded memory or time. Each one, when
// exceeded, is a clear BadInput error naming the file and the limit. Every limit can be
// raised (or lowered) with --limit NAME=VALUE for scenes that are large on purpose.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clpt {

struct LoadLimits {
  uint64_t file_bytes = (uint64_t{1} << 31) - 1;   // any single file read (scene, .bin, image)
  uint64_t total_bytes = uint64_t{1} << 32;        // all files of one scene together
  uint64_t json_depth = 256;                       // nesting of JSON arrays/objects
  uint64_t accessor_count = uint64_t{1} << 30;     // elements in one accessor
  uint64_t zero_accessor_count = uint64_t{1} << 20;  // elements read from accessors without
                                                   // bufferView, all reads together (zeros:
                                                   // memory that costs the file no bytes)
  uint64_t vertices = uint64_t{1} << 28;           // in the whole scene, after instancing
  uint64_t triangles = uint64_t{1} << 28;          // in the whole scene, after instancing
  uint64_t node_depth = 1024;                      // depth of the node hierarchy
  uint64_t node_visits = uint64_t{1} << 24;        // node visits while walking the scene
  uint64_t image_dimension = 16384;                // width or height of one image
  uint64_t image_pixels = uint64_t{1} << 26;       // pixels of one image (256 MiB as RGBA8)
  uint64_t total_texels = uint64_t{1} << 28;       // texels of all textures (1 GiB as RGBA8; a 16-bit
                                                   // normal map's texel counts twice)
  uint64_t memory_bytes = 0;  // host memory the scene's geometry may need while loading and
                              // flattening (estimated per vertex and triangle); 0: 80 % of
                              // this machine's physical memory
  uint64_t memory_per_file_byte = 1024;  // ... and per byte of the scene's files, at least
                                         // kMinMemoryBudget: instancing and reused meshes
                                         // cannot make a 1 KB file cost gigabytes
  static constexpr uint64_t kMinMemoryBudget = uint64_t{256} << 20;

  // Sets one limit from "NAME=VALUE" (VALUE a non-negative integer, or with a suffix k, M, G
  // for 2^10, 2^20, 2^30). Throws Error(Usage) naming the problem and the known names.
  void set(const std::string& spec);
  // The names set() accepts, with their current values, one per line.
  std::string describe() const;
  // memory_bytes, or 80 % of physical memory when it is 0.
  uint64_t memory_budget() const;
  // The budget for a scene of `file_bytes` bytes: the smaller of memory_budget() and
  // memory_per_file_byte x file_bytes (at least kMinMemoryBudget); `which` (when not null)
  // gets the binding limit, as a message says it: "... (--limit NAME=N changes it)".
  uint64_t memory_budget(uint64_t file_bytes, std::string* which) const;

  // Stack bytes a level of JSON nesting or node depth may take, with room to spare: the
  // parser and the node walk measured about 540 and 670 bytes per level (a Release build
  // crashed past about 15 500 and 12 500 levels in 8 MiB), so 2 KiB a level is a 3x margin.
#if defined(__SANITIZE_ADDRESS__) || defined(CLPT_SANITIZED)
  // AddressSanitizer's redzones make every frame several times larger.
  static constexpr uint64_t kStackBytesPerLevel = 8192;
#else
  static constexpr uint64_t kStackBytesPerLevel = 2048;
#endif
  // This process's stack limit (RLIMIT_STACK; 1 GiB when unlimited), and the deepest
  // json-depth or node-depth it serves: 4 096 under the usual 8 MiB (1 024 in a sanitizer
  // build).
  static uint64_t stack_bytes();
  static uint64_t max_recursion_depth();
};

// Host bytes one vertex and one triangle cost from loading to upload (scene arrays, flattened
// arrays, BVH build; a triangle's 36 bytes of float4 lanes on a CPU device, whose buffer is
// host memory: the peak RSS grew by 36 MiB with 1 M triangles): what the memory limit is
// checked against.
constexpr uint64_t kHostBytesPerVertex = 160;
constexpr uint64_t kHostBytesPerTriangle = 196;

}  // namespace clpt
