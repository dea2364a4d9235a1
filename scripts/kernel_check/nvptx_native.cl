/* Linked before libclc by scripts/kernel_compile_check.py for the nvptx target only.
 * libclc 15 implements these native_ functions for NVPTX as LLVM intrinsics (llvm.log.f32,
 * llvm.cos.f32, ...) that LLVM 15's NVPTX back end cannot lower without unsafe-math (it
 * stops with "Undefined external symbol logf" or "Cannot select fcos"). NVIDIA's own
 * compiler maps them to its approximate instructions. Here they are libclc's full-precision
 * functions, which OpenCL allows for native_ (their precision is implementation-defined), so
 * the kernels' own source is compiled unchanged. */
float __attribute__((overloadable)) native_log(float x) { return log(x); }
float __attribute__((overloadable)) native_log2(float x) { return log2(x); }
float __attribute__((overloadable)) native_exp(float x) { return exp(x); }
float __attribute__((overloadable)) native_exp2(float x) { return exp2(x); }
float __attribute__((overloadable)) native_sin(float x) { return sin(x); }
float __attribute__((overloadable)) native_cos(float x) { return cos(x); }
