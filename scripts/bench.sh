#!/usr/bin/env bash
# Benchmarks clpt with --stats and prints one summary line per run, plus the raw JSON under
# bench-out/. Figures and the exact commands go into docs/BENCHMARKS.md.
#   scripts/bench.sh [--device SPEC] [--build DIR]
# Runs: Cornell box 256x256 at max depth 8 (kernel cold, then cached), and
# ../shared/scenes/MetalRoughSpheresNoTextures (about 1M triangles once instances are flattened).
set -euo pipefail
cd "$(dirname "$0")/.."
device=pocl
build=build
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device="$2"; shift 2;;
    --build) build="$2"; shift 2;;
    *) echo "usage: scripts/bench.sh [--device SPEC] [--build DIR]" >&2; exit 1;;
  esac
done
clpt="$build/clpt"
[ -x "$clpt" ] || { echo "bench: $clpt not built (cmake --build $build)" >&2; exit 1; }
out=bench-out
mkdir -p "$out"
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT

summary() {  # name json
  python3 - "$1" "$2" <<'PY'
import json, sys
name, path = sys.argv[1], sys.argv[2]
j = json.load(open(path))
m = j["memory"]
print(f"{name:<28} {j['resolution'][0]}x{j['resolution'][1]} spp {j['spp']:>4}  "
      f"paths/s {j['camera_paths_per_second']/1e6:7.3f} M  rays/s {j['rays_per_second']/1e6:7.2f} M  "
      f"bvh {j['bvh']['build_seconds']:.3f} s  kernel {j['kernel']['seconds']:.3f} s "
      f"({'cached' if j['kernel']['from_cache'] else 'cold'})  "
      f"scene mem {m['scene_device_bytes_per_triangle']:.1f} B/tri  rss {m['peak_host_rss_mib']:.0f} MiB  "
      f"[{j['device']['name']}]")
PY
}

run() {  # name args...
  local name="$1"; shift
  local cmd=("$clpt" --device="$device" --quiet --stats="$out/$name.json" "$@")
  echo "\$ ${cmd[*]}" >> "$out/commands.txt"
  # Both caches live in a fresh folder: clpt's binary cache and PoCL's own kernel cache, so
  # the first run is truly cold and later runs hit the cache.
  CLPT_CACHE_DIR="$cache/clpt" POCL_CACHE_DIR="$cache/pocl" "${cmd[@]}"
  summary "$name" "$out/$name.json"
}

: > "$out/commands.txt"
run cornell-cold scenes/cornell_box.gltf --resolution 256x256 --max-depth 8 --spp 64 -o "$out/cornell.exr"
run cornell-cached scenes/cornell_box.gltf --resolution 256x256 --max-depth 8 --spp 256 -o "$out/cornell.exr"
spheres=../shared/scenes/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb
if [ -f "$spheres" ]; then
  run spheres-1M "$spheres" --resolution 256x256 --max-depth 8 --spp 256 -o "$out/spheres.exr"
else
  echo "bench: $spheres not found; skipped the 1M-triangle scene" >&2
fi
echo "commands: $out/commands.txt"
