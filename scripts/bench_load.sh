#!/usr/bin/env bash
# Load cost of glTF files: for each FILE, RUNS loads (a 16x16, 1 spp render each) and the
# median of clpt's --stats scene_load_seconds, with the scene's device bytes, triangles and
# peak host RSS of the last run. Files are loaded in turn (A B C A B C ...), so that all see
# the same machine load.
#   scripts/bench_load.sh [-n RUNS] FILE... [-- extra clpt args]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=5
if [ "${1:-}" = "-n" ]; then runs="$2"; shift 2; fi
files=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do files+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
[ ${#files[@]} -gt 0 ] || { echo "usage: scripts/bench_load.sh [-n RUNS] FILE... [-- args]" >&2; exit 1; }
clpt="${CLPT:-build/clpt}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for i in $(seq "$runs"); do
  for k in "${!files[@]}"; do
    "$clpt" --device=pocl --quiet "${files[$k]}" --resolution 16x16 --spp 1 "$@" -o "$tmp/out.exr" \
      --stats="$tmp/$k-$i.json"
  done
done
printf '%-60s %12s %12s %14s %10s\n' file load_s triangles scene_bytes rss_MiB
for k in "${!files[@]}"; do
  python3 - "$tmp" "$k" "$runs" "${files[$k]}" <<'PY'
import json, statistics, sys
tmp, k, runs, name = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
d = [json.load(open(f"{tmp}/{k}-{i}.json")) for i in range(1, runs + 1)]
load = statistics.median(x["scene_load_seconds"] for x in d)
m = d[-1]["memory"]
print(f"{name[-60:]:<60} {load:12.4f} {d[-1]['triangles']:12d} {m['scene_device_bytes']:14d} {m['peak_host_rss_mib']:10.1f}")
PY
done
