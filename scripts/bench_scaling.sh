#!/usr/bin/env bash
# Parallel efficiency of split renders on this machine (issue 20, docs/scaling.md): the
# Cornell box at 256x256, 256 spp, pt, rendered alternately
#   - by one PoCL device and by two (POCL_DEVICES="basic basic", --device 0:0 / 0:0,0:1),
#   - by one process and by two MPI ranks (mpirun -n 2), one PoCL thread per process,
# RUNS times each (default 3), with the median of clpt's own render_seconds (--stats) and the
# efficiency T1 / (2 T2). Then the time the final film takes at 4K (--stats
# "film_gather_seconds", 1 spp at 3840x2160): one process reading its film back, and two ranks,
# rank 0 reading its own and receiving and adding the other's. Options after RUNS replace the
# render's (e.g. --integrator mlt --spp 64: another integrator, also at 256x256), and the 4K
# film's timing is then left out.
#
#   scripts/bench_scaling.sh [RUNS [CLPT-OPTIONS...]]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-3}"
shift || true
render=(--spp 256)
[ $# -gt 0 ] && render=("$@")
clpt=build/clpt
scene=scenes/cornell_box.gltf
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpi=(mpirun --oversubscribe --allow-run-as-root --mca btl_vader_single_copy_mechanism none)
common=(-q --resolution 256x256 --seed 1 "${render[@]}" -o "$out/x.exr")

seconds() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }

one_dev=(); two_dev=(); one_proc=(); two_proc=()
for ((i = 0; i < runs; i++)); do
  POCL_DEVICES="basic basic" "$clpt" "$scene" "${common[@]}" --device 0:0 --stats="$out/s.json"
  one_dev+=("$(seconds "$out/s.json" render_seconds)")
  POCL_DEVICES="basic basic" "$clpt" "$scene" "${common[@]}" --device 0:0,0:1 --stats="$out/s.json"
  two_dev+=("$(seconds "$out/s.json" render_seconds)")
  POCL_MAX_PTHREAD_COUNT=1 "$clpt" "$scene" "${common[@]}" --device pocl --stats="$out/s.json"
  one_proc+=("$(seconds "$out/s.json" render_seconds)")
  "${mpi[@]}" -n 2 -x POCL_MAX_PTHREAD_COUNT=1 "$clpt" "$scene" "${common[@]}" --device pocl --stats="$out/s.json"
  two_proc+=("$(seconds "$out/s.json" render_seconds)")
done
report() {
  local name=$1 t1=$2 t2=$3
  python3 -c "import sys; t1, t2 = float(sys.argv[2]), float(sys.argv[3]); print(f'{sys.argv[1]}: one {t1:.2f} s, two {t2:.2f} s (medians of $runs), speed-up {t1 / t2:.2f}, efficiency {100 * t1 / (2 * t2):.0f} %')" "$name" "$t1" "$t2"
}
echo "runs: devices one ${one_dev[*]} / two ${two_dev[*]}; processes one ${one_proc[*]} / two ${two_proc[*]}"
report "two PoCL devices, one process" "$(median "${one_dev[@]}")" "$(median "${two_dev[@]}")"
report "two MPI ranks, one PoCL thread each" "$(median "${one_proc[@]}")" "$(median "${two_proc[@]}")"
[ "${render[*]}" = "--spp 256" ] || exit 0

POCL_MAX_PTHREAD_COUNT=1 "$clpt" "$scene" -q --resolution 3840x2160 --spp 1 --device pocl \
  -o "$out/4k.exr" --stats="$out/4k1.json"
"${mpi[@]}" -n 2 -x POCL_MAX_PTHREAD_COUNT=1 "$clpt" "$scene" -q --resolution 3840x2160 --spp 1 \
  --device pocl -o "$out/4k.exr" --stats="$out/4k2.json"
echo "4K film (3840x2160): one process read it back in $(seconds "$out/4k1.json" film_gather_seconds) s;" \
  "two ranks: rank 0 read its own and gathered and added rank 1's in $(seconds "$out/4k2.json" film_gather_seconds) s"
