// Non-cryptographic hashes of bytes, through xxHash (Debian's libxxhash-dev, inlined: no
// library is linked). hash64 is XXH64, the function checkpoints and the kernel cache have
// always used (through OpenImageIO's copy until session 43), so their files stay valid;
// hash128 (XXH3, 128 bits) names kernel cache entries.
#pragma once

#include <cstddef>
#include <cstdint>

#define XXH_INLINE_ALL
#include <xxhash.h>
#undef XXH_INLINE_ALL

namespace clpt {

inline uint64_t hash64(const void* data, size_t size, uint64_t seed = 0) { return XXH64(data, size, seed); }

struct Hash128 {
  uint64_t high, low;
};
inline Hash128 hash128(const void* data, size_t size) {
  const XXH128_hash_t h = XXH3_128bits(data, size);
  return {h.high64, h.low64};
}

}  // namespace clpt
