#!/usr/bin/env bash
# Builds clpt with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan, CLPT_SANITIZE=ON)
# and runs the tests that feed clpt hostile or degenerate input: the glTF loader and its
# malformed corpus (Gltf*), clpt-diff and image statistics (ClptDiff*, ImageStats*), the image
# decoders (ImageDecode*, ImageReader*, ImageCodecs*, NormalMap16*: 16-bit PNGs), the
# command line (Cli*, which runs the sanitized clpt), the kernel cache (KernelCache*,
# KernelSource*) and the robustness tests (OutOfMemory*, UnwritableOutput*, BuildFailure*,
# NoNaN*, ScaleInvariance*). Extra arguments go to ctest (e.g. -R Gltf to narrow it).
#
#   scripts/test-sanitize.sh
#
# Any ASan report or UBSan diagnostic aborts the process, so the test fails.
# Leaks: PoCL and the LLVM inside it keep allocations alive until exit by design (the device,
# compiled programs, LLVM's global state); LeakSanitizer reports about 2.8 MB of them at the
# exit of every process that opened an OpenCL context, and that exit status fails the test.
# Those two libraries are suppressed (build-asan/lsan.supp, written below), so leaks in clpt's
# own code are still found. CLPT_SANITIZE_LEAKS=0 turns leak detection off altogether
# (ASAN_OPTIONS=detect_leaks=0). Nothing else is needed for PoCL 3.1 under ASan on Debian 12
# (see docs/robustness.md): the kernels are compiled and run by PoCL's own LLVM, which ASan
# does not instrument, and the device tests pass.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
start=$(date +%s)

# The hostile-input suites that run under the sanitizers. The build compiles only the test
# sources that define one of them (tests/CMakeLists.txt, CLPT_SANITIZE_SUITES).
suites='Gltf[A-Za-z]*|ClptDiff|ImageStats|ImageDecode|ImageCodecs|NormalMap16|ImageReader|LoadLimits|Cli|KernelCache|KernelSource|OutOfMemory|HostileSizes|UnwritableOutput|BuildFailure|ScaleInvariance|NoNaN'
# CMakePresets.json: build-asan, RelWithDebInfo, CLPT_SANITIZE=ON
cmake --preset asan "-DCLPT_SANITIZE_SUITES=$suites"
printf '%s\n' '# Allocations PoCL and LLVM keep until exit by design (scripts/test-sanitize.sh).' \
  'leak:libpocl.so' 'leak:libpocl-devices' 'leak:libLLVM' >build-asan/lsan.supp
export ASAN_OPTIONS="detect_leaks=${CLPT_SANITIZE_LEAKS:-1}:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$PWD/build-asan/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Only PoCL's ICD: the OpenCL ICD loader opens every registered driver in the process, and
# Intel's (intel-opencl-icd, which scripts/install-deps.sh installs for ocloc, as a user's
# machine with an Intel GPU has it) dlopens a library with RTLD_DEEPBIND, which the ASan runtime
# refuses: every sanitized process that touches OpenCL would abort at its first call.
mkdir -p build-asan/icd
rm -f build-asan/icd/*.icd
ln -s /etc/OpenCL/vendors/pocl.icd build-asan/icd/pocl.icd
export OCL_ICD_VENDORS="$PWD/build-asan/icd"
# The test binaries (clpt_tests, clpt_io_tests) and what they run (clpt, clpt-diff); not
# clpt-raybench, which no suite here runs.
cmake --build --preset asan --target clpt_test_binaries
# PoCL's compiled kernels from the Release suite's run, where there was one (scripts/test.sh
# runs it first): the sanitized programs build the same kernel sources with the same options,
# and PoCL finds an entry only under the hash of both, so the CLI tests need not compile every
# integrator again (about 100 s of a clean CI run's 255 s here). The kernels themselves are not
# instrumented either way (PoCL's own LLVM compiles them).
if [ -d build/test-cache/pocl ] && [ ! -e build-asan/test-cache/pocl ]; then
  mkdir -p build-asan/test-cache
  cp -a build/test-cache/pocl build-asan/test-cache/
fi
built=$(date +%s)

# ctest runs a group of a suite per process (tests/GroupTests.cmake): SUITE or SUITE.partK.
tests="(^|/)($suites)(\\.part[0-9]+)?$"
jobs=$(nproc 2>/dev/null || echo 2)
status=0
ctest --test-dir build-asan --output-on-failure -j "$jobs" -R "$tests" "$@" || status=$?
if [ $status -ne 0 ]; then
  # LeakSanitizer's stop-the-world tracer now and then crashes at the exit of a process whose
  # PoCL worker threads are shutting down ("Tracer caught signal 11 ... LeakSanitizer has
  # encountered a fatal error": seen once in about 300 device-test processes here, after the
  # test itself passed; in CI, twice in a row on KernelCache.BuildFailureCarriesTheLog, never
  # reproduced on this machine). That is not a finding, so failed tests run once more; a real
  # ASan, UBSan or leak report is deterministic and fails again.
  echo "test-sanitize: re-running the failed tests once"
  status=0
  log=build-asan/Testing/rerun.log
  ctest --test-dir build-asan --output-on-failure --rerun-failed --output-log "$PWD/$log" || status=$?
  # A test that failed twice only because the leak checker itself crashed was never checked
  # for leaks at all. Run it once more with leak detection off, so that its ASan and UBSan
  # checks still count, and say so. A leak report ("detected memory leaks") never gets here.
  if [ $status -ne 0 ] && grep -q 'LeakSanitizer has encountered a fatal error' "$log" &&
    ! grep -q 'LeakSanitizer: detected memory leaks' "$log"; then
    echo "test-sanitize: LeakSanitizer's tracer crashed again; these tests run once more" \
      "with ASan and UBSan but WITHOUT leak detection:"
    ctest --test-dir build-asan -N --rerun-failed | grep 'Test *#' || true
    status=0
    ASAN_OPTIONS="${ASAN_OPTIONS/detect_leaks=1/detect_leaks=0}" \
      ctest --test-dir build-asan --output-on-failure --rerun-failed || status=$?
  fi
fi
end=$(date +%s)
echo "test-sanitize: build $((built - start)) s, tests $((end - built)) s, total $((end - start)) s"
exit $status
