#!/usr/bin/env bash
# The GPU check (issue 19): run it on any machine with a GPU and its vendor's OpenCL driver,
# from a built tree, and keep what it writes. It
#   1. lists the OpenCL devices (devices.txt);
#   2. renders the Cornell box (then, after the tests, the caustic scene) with every
#      integrator, twice: kernels cold (an empty kernel cache) and cached, with --stats
#      (stats/*.json);
#   3. runs the device-independent tests on the GPU (CLPT_TEST_DEVICE): every program builds,
#      the furnaces against their closed forms, the cross-integrator tests, determinism
#      (tests.log; the gtest summary is printed);
#   4. writes summary.md: device, driver, per integrator the cold and cached kernel build,
#      paths/s and rays/s, and what failed or was skipped.
#
#   scripts/gpu-check.sh [--device SPEC] [--build DIR] [--out DIR] [--seconds S] [--no-tests]
#                        [--budget S]
#
# --device: clpt's device spec (default gpu). --seconds: each render's --time (default 5).
# --build: a build tree, or a bundle from scripts/gpu_bundle.py (a machine without clpt's
# libraries: its lib/ goes on LD_LIBRARY_PATH). --budget: wall seconds for the whole check
# (default none); a step that would start after it is skipped and listed as such, and the
# tests get what is left, so a lent machine's time is never overrun.
# NVIDIA's driver registers no ICD file where only its libraries were installed; when no file
# under /etc/OpenCL/vendors names libnvidia-opencl and the library loads, the check makes a
# private vendors folder naming it (OCL_ICD_VENDORS). It also runs on PoCL (--device pocl) as
# a dry run. Exit status: 0 when every test and render succeeded, 1 otherwise.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
device=gpu build="$root/build" out="$root/gpu-check-out" seconds=5 tests=1 budget=0
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --no-tests) tests=0; shift ;;
    --budget) budget="$2"; shift 2 ;;
    *) sed -n '2,27p' "$0" >&2; exit 2 ;;
  esac
done
clpt="$build/clpt"
[ -x "$clpt" ] || { echo "gpu-check: $clpt is not built (cmake --build $build)" >&2; exit 2; }
mkdir -p "$out/stats"
failed=() skipped=()
[ -d "$build/lib" ] && export LD_LIBRARY_PATH="$build/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
start=$SECONDS
# left: seconds of the budget left (a large number without one).
left() { if [ "$budget" -gt 0 ]; then echo $((budget - (SECONDS - start))); else echo 100000; fi; }

# NVIDIA without an ICD file: name its library in a private vendors folder (by its full
# path when the loader's cache does not know it, as in containers that mount the driver).
nvlib=
if ldconfig -p 2>/dev/null | grep -q 'libnvidia-opencl.so.1'; then
  nvlib=libnvidia-opencl.so.1
else
  nvlib=$(find /usr/local/nvidia /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib -maxdepth 3 \
            -name 'libnvidia-opencl.so.1' 2>/dev/null | head -n 1)
fi
if ! grep -qs libnvidia-opencl /etc/OpenCL/vendors/*.icd && [ -z "${OCL_ICD_VENDORS:-}" ] &&
   [ -n "$nvlib" ]; then
  mkdir -p "$out/icd"
  echo "$nvlib" >"$out/icd/nvidia.icd"
  for f in /etc/OpenCL/vendors/*.icd; do [ -e "$f" ] && ln -sf "$f" "$out/icd/"; done
  export OCL_ICD_VENDORS="$out/icd"
  echo "gpu-check: NVIDIA's OpenCL library is installed without an ICD file; using $out/icd"
fi

"$clpt" --list-devices >"$out/devices.txt" 2>&1 || failed+=("list-devices")
cat "$out/devices.txt"

integrators="pt lt bdpt pm sppm vcm mlt ic ao direct indirect1"
kernel_cache=$(mktemp -d)
trap 'rm -rf "$kernel_cache"' EXIT
render_scene() {
  local scene=$1 integ run limit json cold_env
  for integ in $integrators; do
    for run in cold cached; do
      if [ "$(left)" -lt $((seconds + 20)) ]; then
        skipped+=("$integ/$scene/$run")
        continue
      fi
      # cold: clpt's kernel cache emptied, and the drivers' own caches off (NVIDIA's
      # ComputeCache, PoCL's kernel cache), so the figure is a whole build from source.
      cold_env=()
      if [ "$run" = cold ]; then
        rm -rf "${kernel_cache:?}"/*
        cold_env=(CUDA_CACHE_DISABLE=1 POCL_KERNEL_CACHE=0)
      fi
      json="$out/stats/$integ-$scene-$run.json"
      limit=$(left); [ "$limit" -gt 900 ] && limit=900
      if ! env "${cold_env[@]}" CLPT_CACHE_DIR="$kernel_cache" timeout "$limit" "$clpt" --device "$device" -q \
             "$root/scenes/$scene.gltf" --integrator "$integ" --resolution 256x256 \
             --time "$seconds" -o "$out/stats/$integ-$scene.exr" --stats "$json" \
             >"$out/stats/$integ-$scene-$run.log" 2>&1; then
        failed+=("$integ/$scene/$run")
        tail -n 5 "$out/stats/$integ-$scene-$run.log"
      fi
    done
  done
}

# The tests read the sources through the path they were built from; a tree copied elsewhere
# (a lent GPU machine) gets a link from that path to here when it is free.
run_tests() {
  [ "$tests" = 1 ] || return 0
  src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null)
  if [ -n "$src" ] && [ ! -e "$src" ]; then
    mkdir -p "$(dirname "$src")" && ln -s "$root" "$src" &&
      echo "gpu-check: linked $src -> $root (the tests' source path)"
  fi
  filter='KernelPrograms.EveryProgramBuilds:*SphereFurnace*:*EstimatorFurnace*:CrossIntegrator.*:Determinism.*:MltStationary.*'
  limit=$(left); [ "$limit" -gt 1800 ] && limit=1800
  if [ "$limit" -lt 30 ]; then
    skipped+=("tests")
  else
    cache=$(mktemp -d)
    XDG_CACHE_HOME="$cache" CLPT_TEST_DEVICE="$device" timeout "$limit" \
      "$build/tests/clpt_tests" --gtest_filter="$filter" >"$out/tests.log" 2>&1 || failed+=("tests")
    rm -rf "$cache"
    grep -E '^\[  (PASSED|FAILED) |^\[==========\]|^\[       OK \]' "$out/tests.log" | tail -n 40
  fi
}

# Most telling first, in case the budget ends the check: the Cornell box, the tests, the
# caustic scene.
render_scene cornell_box
run_tests
render_scene caustic

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
if [ ${#skipped[@]} -gt 0 ]; then
  echo "gpu-check: skipped (budget): ${skipped[*]}" | tee -a "$out/summary.md"
fi
if [ ${#failed[@]} -gt 0 ]; then
  echo "gpu-check: failed: ${failed[*]}" | tee -a "$out/summary.md"
  exit 1
fi
echo "gpu-check: all that ran passed (${#skipped[@]} skipped); figures in $out"
