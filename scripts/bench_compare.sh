#!/usr/bin/env bash
# Compares the speed of two clpt builds on the same scene, alternating runs (A B A B ...) so
# that both see the same machine load, and prints each run's camera paths/s and the medians.
#   scripts/bench_compare.sh BASE_CLPT NEW_CLPT [runs] [-- extra clpt args]
# Default scene: the Cornell box, 256x256, 256 spp, max depth 8, PoCL.
# A base build of an older commit: git worktree add /tmp/base COMMIT &&
#   cmake -S /tmp/base -B /tmp/base/build -G Ninja -DCMAKE_BUILD_TYPE=Release &&
#   cmake --build /tmp/base/build --target clpt
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: scripts/bench_compare.sh BASE_CLPT NEW_CLPT [runs] [-- args]" >&2; exit 1; }
base="$1" new="$2"; shift 2
runs=5
if [ $# -gt 0 ] && [ "$1" != "--" ]; then runs="$1"; shift; fi
[ "${1:-}" = "--" ] && shift
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(scenes/cornell_box.gltf --resolution 256x256 --spp 256 --max-depth 8)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for bin in "$base" "$new"; do  # warm both kernel caches
  "$bin" --device=pocl --quiet "${args[@]}" -o "$tmp/warm.exr"
done
for i in $(seq "$runs"); do
  for which in base new; do
    bin=$base; [ $which = new ] && bin=$new
    "$bin" --device=pocl --quiet "${args[@]}" -o "$tmp/$which.exr" --stats="$tmp/$which-$i.json"
    python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['camera_paths_per_second'])" \
      "$tmp/$which-$i.json" >> "$tmp/$which.txt"
  done
done
python3 - "$tmp" <<'PY'
import statistics, sys
d = sys.argv[1]
res = {w: [float(x) for x in open(f"{d}/{w}.txt")] for w in ("base", "new")}
for w, v in res.items():
    print(f"{w:>4}: " + " ".join(f"{x/1e6:.3f}" for x in v) + f"  median {statistics.median(v)/1e6:.3f} M paths/s")
b, n = statistics.median(res["base"]), statistics.median(res["new"])
print(f"new / base = {n / b:.3f} ({(n / b - 1) * 100:+.1f} %)")
PY
