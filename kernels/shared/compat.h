/* Lets one header declare structs for both the C++ host and OpenCL C.
 * Shared structs use only 32-bit scalars and float arrays: no float3 (its size and
 * alignment differ between host and device) and no vector types. On the host the structs
 * live in namespace clpt::dev; the host static_asserts their sizes and a test kernel
 * compares sizeof/offsetof with the device compiler's. */
#ifndef CLPT_SHARED_COMPAT_H
#define CLPT_SHARED_COMPAT_H

/* OpenCL C compilers do not agree on one macro: PoCL and the vendors' drivers define
 * __OPENCL_VERSION__, clang alone (its NVPTX and AMDGPU targets) only __OPENCL_C_VERSION__. */
#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
#define CLPT_OPENCL_DEVICE 1
#endif

#ifdef CLPT_OPENCL_DEVICE
typedef uint u32;
typedef int i32;
#define CLPT_BEGIN_SHARED
#define CLPT_END_SHARED
#else
#include <cstdint>
#define CLPT_BEGIN_SHARED namespace clpt { namespace dev { typedef std::uint32_t u32; typedef std::int32_t i32;
#define CLPT_END_SHARED } }
#endif

#endif
