#!/usr/bin/env bash
# The GPU check (issue 19): run it on any machine with a GPU and its vendor's OpenCL driver,
# from a built tree, and keep what it writes. It
#   1. lists the OpenCL devices (devices.txt);
#   2. runs the device-independent tests on the GPU (CLPT_TEST_DEVICE): every program builds,
#      the furnaces against their closed forms, the cross-integrator tests, determinism
#      (tests.log; the gtest summary is printed);
#   3. renders the Cornell box and the caustic scene with every integrator, twice: kernels
#      cold (an empty kernel cache) and cached, with --stats (stats/*.json);
#   4. writes summary.md: device, driver, per integrator the cold and cached kernel build,
#      paths/s and rays/s, and what failed.
#
#   scripts/gpu-check.sh [--device SPEC] [--build DIR] [--out DIR] [--seconds S] [--no-tests]
#
# --device: clpt's device spec (default gpu). --seconds: each render's --time (default 5).
# NVIDIA's driver registers no ICD file where only its libraries were installed; when no file
# under /etc/OpenCL/vendors names libnvidia-opencl and the library loads, the check makes a
# private vendors folder naming it (OCL_ICD_VENDORS). It also runs on PoCL (--device pocl) as
# a dry run. Exit status: 0 when every test and render succeeded, 1 otherwise.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
device=gpu build="$root/build" out="$root/gpu-check-out" seconds=5 tests=1
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --no-tests) tests=0; shift ;;
    *) sed -n '2,20p' "$0" >&2; exit 2 ;;
  esac
done
clpt="$build/clpt"
[ -x "$clpt" ] || { echo "gpu-check: $clpt is not built (cmake --build $build)" >&2; exit 2; }
mkdir -p "$out/stats"
failed=()

# NVIDIA without an ICD file: name its library in a private vendors folder.
if ! grep -qs libnvidia-opencl /etc/OpenCL/vendors/*.icd && [ -z "${OCL_ICD_VENDORS:-}" ] &&
   ldconfig -p 2>/dev/null | grep -q 'libnvidia-opencl.so.1'; then
  mkdir -p "$out/icd"
  echo libnvidia-opencl.so.1 >"$out/icd/nvidia.icd"
  for f in /etc/OpenCL/vendors/*.icd; do [ -e "$f" ] && ln -sf "$f" "$out/icd/"; done
  export OCL_ICD_VENDORS="$out/icd"
  echo "gpu-check: NVIDIA's OpenCL library is installed without an ICD file; using $out/icd"
fi

"$clpt" --list-devices >"$out/devices.txt" 2>&1 || failed+=("list-devices")
cat "$out/devices.txt"

# The tests read the sources through the path they were built from; a tree copied elsewhere
# (a lent GPU machine) gets a link from that path to here when it is free.
if [ "$tests" = 1 ]; then
  src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null)
  if [ -n "$src" ] && [ ! -e "$src" ]; then
    mkdir -p "$(dirname "$src")" && ln -s "$root" "$src" &&
      echo "gpu-check: linked $src -> $root (the tests' source path)"
  fi
  filter='KernelPrograms.EveryProgramBuilds:*SphereFurnace*:*EstimatorFurnace*:CrossIntegrator.*:Determinism.*:MltStationary.*'
  cache=$(mktemp -d)
  XDG_CACHE_HOME="$cache" CLPT_TEST_DEVICE="$device" timeout 1800 \
    "$build/tests/clpt_tests" --gtest_filter="$filter" >"$out/tests.log" 2>&1 || failed+=("tests")
  rm -rf "$cache"
  grep -E '^\[  (PASSED|FAILED) |^\[==========\]' "$out/tests.log" | tail -n 20
fi

integrators="pt lt bdpt pm sppm vcm mlt ic ao direct indirect1"
kernel_cache=$(mktemp -d)
trap 'rm -rf "$kernel_cache"' EXIT
for scene in cornell_box caustic; do
  for integ in $integrators; do
    for run in cold cached; do
      # cold: clpt's kernel cache emptied, and the drivers' own caches off (NVIDIA's
      # ComputeCache, PoCL's kernel cache), so the figure is a whole build from source.
      cold_env=()
      if [ "$run" = cold ]; then
        rm -rf "${kernel_cache:?}"/*
        cold_env=(CUDA_CACHE_DISABLE=1 POCL_KERNEL_CACHE=0)
      fi
      json="$out/stats/$integ-$scene-$run.json"
      if ! env "${cold_env[@]}" CLPT_CACHE_DIR="$kernel_cache" timeout 900 "$clpt" --device "$device" -q \
             "$root/scenes/$scene.gltf" --integrator "$integ" --resolution 256x256 \
             --time "$seconds" -o "$out/stats/$integ-$scene.exr" --stats "$json" \
             >"$out/stats/$integ-$scene-$run.log" 2>&1; then
        failed+=("$integ/$scene/$run")
        tail -n 5 "$out/stats/$integ-$scene-$run.log"
      fi
    done
  done
done

python3 - "$out" <<'PY' >"$out/summary.md"
import glob, json, os, sys
out = sys.argv[1]
rows, dev = [], None
for cold in sorted(glob.glob(os.path.join(out, "stats", "*-cold.json"))):
    cached = cold.replace("-cold.json", "-cached.json")
    c = json.load(open(cold))
    w = json.load(open(cached)) if os.path.exists(cached) else None
    dev = dev or c["device"]
    r = w or c
    paths = r.get("camera_paths_per_second", r.get("light_paths_per_second", 0.0))
    rows.append("| %s | %s | %.2f | %s | %.3f%s | %.1f | %d |" % (
        c["integrator"], os.path.basename(c["scene"]), c["kernel"]["seconds"],
        "%.2f" % w["kernel"]["seconds"] if w else "-", paths / 1e6,
        "" if "camera_paths_per_second" in r else " (light)", r["rays_per_second"] / 1e6, r["spp"]))
if dev:
    print("Device: %s (%s, %s, driver %s, %d compute units)\n" % (
        dev["name"], dev["platform"], dev["version"], dev["driver"], dev["compute_units"]))
print("| integrator | scene | kernels cold s | kernels cached s | M paths/s | M rays/s | spp (cached run) |")
print("|---|---|---|---|---|---|---|")
print("\n".join(rows))
PY
cat "$out/summary.md"
if [ ${#failed[@]} -gt 0 ]; then
  echo "gpu-check: failed: ${failed[*]}" | tee -a "$out/summary.md"
  exit 1
fi
echo "gpu-check: all passed; figures in $out"
