#!/usr/bin/env bash
# The GPU check (issue 19): run it on any machine with a GPU and its vendor's OpenCL driver,
# from a built tree, and keep what it writes. It
#   1. lists the OpenCL devices (devices.txt);
#   2. builds every integrator's kernel programs, all at once, one clpt process each (a
#      driver compiles a program on one core, and NVIDIA's took 37 to 153 s a program on an
#      H200: one after another they would not fit a lent machine's 15 minutes), with empty
#      caches: the cold build time (stats/INTEG-build.json; on NVIDIA each kernel's registers
#      and spills from -cl-nv-verbose in stats/INTEG-build.log);
#   3. renders the Cornell box with every integrator, one after another, with the caches
#      warm (clpt's and the driver's own): the start-up a user sees from the second run on,
#      paths/s and rays/s (stats/INTEG-cornell_box.json); on NVIDIA pt once more with the
#      driver's cache off (stats/pt-nvcache-off.json): clpt's cache holds PTX there, and this is
#      what assembling it costs at every start without the driver's cache;
#   3b. times the BVH traversal alone (clpt-raybench, when built): Embree's benchmark ray
#      sets on the Cornell box and on scripts/make_spheres_1m.py's 1M triangles
#      (stats/raybench-SCENE.json), for figures beside the CPU's in docs/BENCHMARKS.md;
#   4. runs the device-independent tests on the GPU (CLPT_TEST_DEVICE): every program builds,
#      the furnaces against their closed forms, the cross-integrator tests, determinism
#      (tests.log; the gtest summary is printed);
#   5. renders the caustic scene with every integrator (caches warm);
#   6. writes summary.md: device, driver, per integrator the cold build, the warm start,
#      paths/s and rays/s, and what failed or was skipped.
#
#   scripts/gpu-check.sh [--device SPEC] [--build DIR] [--out DIR] [--seconds S] [--no-tests]
#                        [--budget S] [--jobs N]
#
# --device: clpt's device spec (default gpu). --seconds: each timed render's --time (default
# 5). --build: a build tree, or a bundle from scripts/gpu_bundle.py (a machine without clpt's
# libraries: its lib/ goes on LD_LIBRARY_PATH). --budget: wall seconds for the whole check
# (default none): the parallel builds get at most half of it, a later step that would start
# after it is skipped and listed as such, and the tests get what is left, so a lent machine's
# time is never overrun. --jobs: builds at once (default: the number of cores).
# NVIDIA's driver registers no ICD file where only its libraries were installed; when no file
# under /etc/OpenCL/vendors names libnvidia-opencl and the library is found, the check makes
# a private vendors folder naming it (OCL_ICD_VENDORS). It also runs on PoCL (--device pocl)
# as a dry run. Exit status: 0 when every test and render that ran succeeded, 1 otherwise.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
device=gpu build="$root/build" out="$root/gpu-check-out" seconds=5 tests=1 budget=0
jobs=$(nproc 2>/dev/null || echo 4)
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --no-tests) tests=0; shift ;;
    --budget) budget="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    *) sed -n '2,37p' "$0" >&2; exit 2 ;;
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
# cap N: the smaller of N and what is left.
cap() { local l; l=$(left); [ "$l" -lt "$1" ] && echo "$l" || echo "$1"; }

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
nvidia=0
[ "$device" != pocl ] && grep -q 'NVIDIA' "$out/devices.txt" && nvidia=1

# Both caches start empty and are shared by every step after the builds: clpt's (written
# atomically, so parallel builds may share it) and, on NVIDIA, the driver's own.
kernel_cache=$(mktemp -d)
trap 'rm -rf "$kernel_cache"' EXIT
export CLPT_CACHE_DIR="$kernel_cache/clpt"
if [ "$nvidia" = 1 ]; then
  export CUDA_CACHE_PATH="$kernel_cache/nv" CUDA_CACHE_MAXSIZE=4294967296
  export CLPT_BUILD_OPTIONS="-cl-nv-verbose"
fi

integrators="pt lt bdpt pm sppm vcm mlt ic ao direct indirect1"

# render NAME LIMIT ARGS...: one clpt run, its stats in stats/NAME.json, its output in
# stats/NAME.log; a failure is listed.
render() {
  local name=$1 limit=$2
  shift 2
  if ! timeout "$limit" "$clpt" --device "$device" "$@" --stats "$out/stats/$name.json" \
         >"$out/stats/$name.log" 2>&1; then
    failed+=("$name")
    tail -n 5 "$out/stats/$name.log"
  fi
}

# 2. Cold builds, in parallel (-v: the build log, which carries NVIDIA's per-kernel figures).
# A subshell's failed+= is lost: a build counts as failed when it wrote no stats.
build_limit=1800
[ "$budget" -gt 0 ] && build_limit=$((budget / 2))
running=0
for integ in $integrators; do
  ( POCL_KERNEL_CACHE=0 render "$integ-build" "$build_limit" -v "$root/scenes/cornell_box.gltf" \
      --integrator "$integ" --resolution 32x32 --spp 1 -o "$out/stats/$integ-build.exr" ) &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait
for integ in $integrators; do
  [ -s "$out/stats/$integ-build.json" ] || failed+=("$integ-build")
done

# 3. The Cornell box with warm caches, one integrator at a time.
render_scene() {
  local scene=$1 integ
  for integ in $integrators; do
    if [ "$(left)" -lt $((seconds + 20)) ]; then skipped+=("$integ-$scene"); continue; fi
    render "$integ-$scene" "$(cap 900)" -q "$root/scenes/$scene.gltf" --integrator "$integ" \
      --resolution 256x256 --time "$seconds" -o "$out/stats/$integ-$scene.exr"
  done
}
render_scene cornell_box
if [ "$nvidia" = 1 ]; then
  if [ "$(left)" -lt 200 ]; then skipped+=("pt-nvcache-off"); else
    CUDA_CACHE_DISABLE=1 render pt-nvcache-off "$(cap 300)" -q "$root/scenes/cornell_box.gltf" \
      --resolution 64x64 --spp 1 -o "$out/stats/pt-nvcache-off.exr"
  fi
fi

# 3b. The traversal alone (clpt-raybench), on the Cornell box and on 1M generated triangles.
raybench() {
  local name=$1 scene=$2
  if [ "$(left)" -lt 60 ]; then skipped+=("raybench-$name"); return 0; fi
  timeout "$(cap 300)" "$build/clpt-raybench" "$scene" --device "$device" --seconds 2 \
    --json "$out/stats/raybench-$name.json" >"$out/stats/raybench-$name.log" 2>&1 ||
    failed+=("raybench-$name")
}
if [ -x "$build/clpt-raybench" ]; then
  raybench cornell_box "$root/scenes/cornell_box.gltf"
  if python3 "$root/scripts/make_spheres_1m.py" "$out/stats/spheres_1m.glb" >/dev/null 2>&1; then
    raybench spheres_1m "$out/stats/spheres_1m.glb"
    rm -f "$out/stats/spheres_1m.glb"
  fi
fi

# 4. The tests read the sources through the path they were built from; a tree copied
# elsewhere (a lent GPU machine) gets a link from that path to here when it is free.
run_tests() {
  [ "$tests" = 1 ] || return 0
  src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null)
  if [ -n "$src" ] && [ ! -e "$src" ]; then
    mkdir -p "$(dirname "$src")" && ln -s "$root" "$src" &&
      echo "gpu-check: linked $src -> $root (the tests' source path)"
  fi
  filter='KernelPrograms.EveryProgramBuilds:*SphereFurnace*:*EstimatorFurnace*:CrossIntegrator.*:Determinism.*:MltStationary.*'
  local limit
  limit=$(cap 1800)
  if [ "$limit" -lt 30 ]; then skipped+=("tests"); return 0; fi
  CLPT_TEST_DEVICE="$device" timeout "$limit" \
    "$build/tests/clpt_tests" --gtest_filter="$filter" >"$out/tests.log" 2>&1
  case $? in
    0) ;;
    124) skipped+=("tests (cut at ${limit}s)") ;;
    *) failed+=("tests") ;;
  esac
  grep -E '^\[  (PASSED|FAILED) |^\[==========\]|^\[       OK \]' "$out/tests.log" | tail -n 40
}
run_tests

# 5. The caustic scene.
render_scene caustic

# 6. The summary.
python3 - "$out" "$integrators" <<'PY' >"$out/summary.md"
import glob, json, os, re, sys
out, integrators = sys.argv[1], sys.argv[2].split()
stats = os.path.join(out, "stats")
def load(name):
    try:
        return json.load(open(os.path.join(stats, name + ".json")))
    except (OSError, ValueError):
        return None
dev, rows = None, []
for scene in ("cornell_box", "caustic"):
    for integ in integrators:
        b, r = load(integ + "-build"), load("%s-%s" % (integ, scene))
        if not (b or r) or (scene != "cornell_box" and not r):
            continue
        dev = dev or (b or r)["device"]
        cells = ["%.1f" % b["kernel"]["seconds"] if b else "-"]
        if r:
            light = "camera_paths_per_second" not in r
            paths = r.get("camera_paths_per_second", r.get("light_paths_per_second", 0.0))
            cells += ["%.1f" % r["kernel"]["seconds"], "%.2f%s" % (paths / 1e6, " (light)" if light else ""),
                      "%.0f" % (r["rays_per_second"] / 1e6), "%d" % r["spp"]]
        else:
            cells += ["-"] * 4
        rows.append("| %s | %s | %s |" % (integ, scene, " | ".join(cells)))
if dev:
    print("Device: %s (%s, %s, driver %s, %d compute units)\n" % (
        dev["name"], dev["platform"], dev["version"], dev["driver"], dev["compute_units"]))
print("| integrator | scene | cold build s (in parallel) | warm start s | M paths/s | M rays/s | spp |")
print("|---|---|---|---|---|---|---|")
print("\n".join(rows))
try:
    log = open(os.path.join(out, "tests.log"), errors="replace").read()
    ok, bad = len(re.findall(r"^\[       OK \]", log, re.M)), len(re.findall(r"^\[  FAILED  \] \S+\.", log, re.M))
    done = re.search(r"^\[==========\] (\d+) tests? from .* ran", log, re.M)
    print("\nTests on the device: %d passed, %d failed%s" % (
        ok, bad, "" if done else " (cut before the end: tests.log)"))
except OSError:
    pass
bench = [(name, load("raybench-" + name)) for name in ("cornell_box", "spheres_1m")]
if any(b for _, b in bench):
    print("\n| traversal alone (clpt-raybench) | triangles | BVH build s | " +
          " | ".join(f["name"] + " M rays/s" for f in next(b for _, b in bench if b)["figures"]) + " |")
    print("|---|---|---|---|---|---|")
    for name, b in bench:
        if b:
            print("| %s | %d | %.3f | %s |" % (name, b["triangles"], b["bvh_build_seconds"], " | ".join(
                "%.2f (hits %.3f)" % (f["mrays_per_second"], f["hit_rate"]) for f in b["figures"])))
off = load("pt-nvcache-off")
if off:
    print("\npt with the driver's cache off, clpt's cache warm: %.1f s to start" % off["kernel"]["seconds"])
# NVIDIA's -cl-nv-verbose lines in the build logs: registers and spills per kernel.
regs = []
for log in sorted(glob.glob(os.path.join(stats, "*-build.log"))):
    kernel = None
    for line in open(log, errors="replace"):
        m = re.search(r"Compiling entry function '(\w+)'", line)
        if m:
            kernel = m.group(1)
        m = re.search(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", line)
        if m and kernel:
            regs.append([kernel, m.group(1), m.group(2), m.group(3), ""])
        m = re.search(r"Used (\d+) registers", line)
        if m and kernel and regs and regs[-1][0] == kernel:
            regs[-1][4] = m.group(1)
if regs:
    print("\n| kernel (driver's build log) | stack bytes | spill stores | spill loads | registers |")
    print("|---|---|---|---|---|")
    seen = set()
    for r in regs:
        if r[0] not in seen:
            seen.add(r[0])
            print("| " + " | ".join(r) + " |")
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
