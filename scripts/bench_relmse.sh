#!/usr/bin/env bash
# Equal-time relMSE of integrators against a high-spp path-traced reference (issue 5: bdpt
# against pt on scenes/caustic.gltf and scenes/indirect.gltf).
#
#   scripts/bench_relmse.sh SCENE SECONDS INTEGRATOR... [-- extra clpt args]
#   e.g. scripts/bench_relmse.sh scenes/caustic.gltf 10 pt bdpt
#        REF_SPP=65536 scripts/bench_relmse.sh scenes/indirect.gltf 30 pt lt bdpt -- --rr-depth 5
#
# 1. Reference: REF_INTEGRATOR (pt) at REF_SPP samples per pixel, rendered as REF_PARTS (2)
#    independent parts of REF_SPP/REF_PARTS spp (seeds 1000001, 1000002, ...) averaged with
#    oiiotool. It is cached under $BENCH_DIR/<scene>/ref-<key>/, the key being a hash of the
#    scene file's bytes, RES, DEPTH, REF_SPP, REF_PARTS (when not 2), REF_INTEGRATOR, DEVICE and
#    the extra clpt args; a later run with the same key reuses it (delete the folder to render
#    it again). The parts are cached apart, under parts-<key>/ (the same key less REF_SPP and
#    REF_PARTS, plus the part's spp), so a longer reference reuses the parts rendered before:
#    REF_SPP=65536 REF_PARTS=4 after REF_SPP=32768 renders parts 3 and 4 only (the halves of an
#    earlier two-part reference count as parts 1 and 2).
#    REF=DIR|FILE uses a reference made elsewhere instead (e.g. with many more samples on a
#    GPU): a ref-<key> folder of this script, or an EXR (its spp from the file's clpt:spp; its
#    own error is known only when a reference.txt written by this script lies beside it).
# 2. Each INTEGRATOR renders for SECONDS (clpt --time: render time only, not the scene load or
#    the kernel build) at the same resolution and depth, with seed SEED, and writes --stats;
#    RUNS > 1 repeats that with seeds SEED, SEED+1, ... and averages (relMSE is heavy-tailed
#    where an estimator makes fireflies, so one run can be far from the mean; a second table
#    then gives each integrator's mean relMSE, its standard error, the median and every
#    run's figure, since a firefly shared by all integrators at one seed can carry the means of
#    a few runs). Names are
#    passed through to clpt --integrator unchecked; a render that fails is reported in the
#    table and the script goes on with the next one (exit status 1 at the end). A name may
#    carry that integrator's own options after commas: `indirect1,--indirect=source` renders
#    --integrator indirect1 --indirect=source (REF_INTEGRATOR too).
# 3. clpt-diff --json gives each image's relMSE against the reference; the table lists
#    integrator, spp reached (--stats), render seconds, relMSE, relMSE less the reference's
#    own error, and relMSE(pt) / relMSE(integrator) (raw, and with that error removed) when
#    pt is one of the integrators. With RUNS > 1 these are means over the runs.
#
# The reference's own noise. The reference is itself a Monte Carlo (pt) render, and every
# relMSE measured against it is, in expectation, relMSE(image vs truth) + relMSE(reference vs
# truth): the reference's error is a floor under every figure, and it pulls every ratio towards
# 1. It must therefore lie well below the relMSE values measured (a tenth of the smallest at
# most). The script estimates it as a quarter of the relMSE between the two independent halves
# (the average of two halves has half the variance of one half; two halves differ by twice
# that; with n parts, the mean relMSE of the disjoint pairs (1, 2), (3, 4), ... over 2n),
# prints it with the reference's spp and seconds, and warns when it is above a tenth of
# some integrator's relMSE. Raise REF_SPP until it is not. On the caustic scene a pt reference
# converges very slowly (the caustic is found only when a BSDF-sampled path happens to hit the
# small light through the glass, and each such sample is a firefly), so there the floor stays
# far above any good estimator's relMSE at spp a CPU can afford: render that reference with
# many more samples on a GPU (REF), or, once bdpt is shown unbiased, with REF_INTEGRATOR=bdpt.
# Without oiiotool the reference is one render of REF_SPP and its error is not estimated.
#
# Environment (defaults in brackets):
#   CLPT [build/clpt], CLPT_DIFF [build/clpt-diff]  binaries (relative to the repository root
#                                                    when the default is used)
#   BENCH_DIR [bench-out/relmse]  reference cache and per-run outputs
#   REF_SPP [4096]  REF_PARTS [2]  RES [128x128]  DEPTH [8]  (--max-depth, for every render)
#   REF_INTEGRATOR [pt]  REF [unset]  SEED [1] (the timed renders' first --seed)  RUNS [1]
#   DEVICE [pocl] (clpt --device, every render)
# Each run writes its images, stats, diffs, commands.txt and table.txt to
# $BENCH_DIR/<scene>/run-<date>-<time>-XXXX/. Renders run one after the other, never in parallel.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
usage() {
  echo "usage: scripts/bench_relmse.sh SCENE SECONDS INTEGRATOR... [-- extra clpt args]" >&2
  exit 2
}
[ $# -ge 3 ] || usage
scene=$1 seconds=$2
shift 2
integrators=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do integrators+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
extra=("$@")
[ ${#integrators[@]} -ge 1 ] || usage
[ -f "$scene" ] || { echo "bench_relmse: scene $scene not found" >&2; exit 2; }
python3 -c 'import sys; assert float(sys.argv[1]) > 0' "$seconds" 2>/dev/null ||
  { echo "bench_relmse: SECONDS must be a positive number, not '$seconds'" >&2; exit 2; }

CLPT=${CLPT:-$root/build/clpt}
CLPT_DIFF=${CLPT_DIFF:-$root/build/clpt-diff}
BENCH_DIR=${BENCH_DIR:-$root/bench-out/relmse}
REF_SPP=${REF_SPP:-4096}
REF_PARTS=${REF_PARTS:-2}
RES=${RES:-128x128}
DEPTH=${DEPTH:-8}
REF_INTEGRATOR=${REF_INTEGRATOR:-pt}
SEED=${SEED:-1}
RUNS=${RUNS:-1}
REF=${REF:-}
DEVICE=${DEVICE:-pocl}
for tool in "$CLPT" "$CLPT_DIFF"; do
  [ -x "$tool" ] || { echo "bench_relmse: $tool not found or not executable (set CLPT / CLPT_DIFF)" >&2; exit 2; }
done
case "$REF_SPP" in '' | *[!0-9]*) echo "bench_relmse: REF_SPP must be a whole number" >&2; exit 2;; esac
case "$REF_PARTS" in '' | *[!0-9]* | 0 | 1) echo "bench_relmse: REF_PARTS must be a whole number of at least 2" >&2; exit 2;; esac
[ $((REF_SPP % REF_PARTS)) -eq 0 ] && [ "$REF_SPP" -ge "$REF_PARTS" ] ||
  { echo "bench_relmse: REF_SPP ($REF_SPP) must be a positive multiple of REF_PARTS ($REF_PARTS)" >&2; exit 2; }
case "$RUNS" in '' | *[!0-9]* | 0) echo "bench_relmse: RUNS must be a positive whole number" >&2; exit 2;; esac
case "$SEED" in '' | *[!0-9]*) echo "bench_relmse: SEED must be a whole number" >&2; exit 2;; esac
if [ "$SEED" -le $((1000000 + REF_PARTS)) ] && [ $((SEED + RUNS - 1)) -ge 1000001 ]; then
  echo "bench_relmse: seeds $SEED..$((SEED + RUNS - 1)) include a reference seed (1000001..$((1000000 + REF_PARTS)))" >&2; exit 2
fi
oiiotool=$(command -v oiiotool || true)

name=$(basename "$scene")
name=${name%.*}
common=(--device "$DEVICE" --quiet --resolution "$RES" --max-depth "$DEPTH")
scene_hash=$(sha256sum < "$scene" | cut -d' ' -f1)
ref_key() {  # REF_SPP [PARTS]: the cache key of a reference (two parts: the key it always had)
  { echo "$scene_hash"
    printf '%s\n' "$RES" "$DEPTH" "$1" "$REF_INTEGRATOR" "$DEVICE" "${oiiotool:+halves}" "${extra[@]+"${extra[@]}"}"
    [ "${2:-2}" -eq 2 ] || echo "parts=$2"
  } | sha256sum | cut -c1-12
}
key=$(ref_key "$REF_SPP" "$REF_PARTS")
part_spp=$((REF_SPP / REF_PARTS))
partdir=$BENCH_DIR/$name/parts-$( { echo "$scene_hash"
  printf '%s\n' "$RES" "$DEPTH" "part=$part_spp" "$REF_INTEGRATOR" "$DEVICE" "${extra[@]+"${extra[@]}"}"
} | sha256sum | cut -c1-12)
refdir=$BENCH_DIR/$name/ref-$key
if [ -n "$REF" ]; then
  if [ -d "$REF" ]; then refdir=$REF; else refdir=$(dirname "$REF"); fi
fi
mkdir -p "$refdir" "$BENCH_DIR/$name"
rundir=$(mktemp -d "$BENCH_DIR/$name/run-$(date +%Y%m%d-%H%M%S)-XXXX")
log() { echo "bench_relmse: $*" >&2; }

render() {  # out.exr stats.json args...: one clpt render; logs the command
  local out=$1 stats=$2
  shift 2
  local cmd=("$CLPT" "$scene" "${common[@]}" "$@" --stats="$stats" -o "$out" ${extra[@]+"${extra[@]}"})
  printf '%q ' "${cmd[@]}" >> "$rundir/commands.txt"
  echo >> "$rundir/commands.txt"
  "${cmd[@]}"
}
integrator_args() {  # NAME[,OPTION...]: --integrator NAME OPTION... (words without spaces)
  local IFS=,
  local parts=($1)
  printf '%s\n' --integrator "${parts[@]}"
}
json() {  # file python-expression-on-j
  python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); v = eval(sys.argv[2]); print("" if v is None else v)' "$1" "$2"
}

# ---- reference --------------------------------------------------------------------------------
ref=$refdir/reference.exr
if [ -n "$REF" ] && [ ! -d "$REF" ]; then ref=$REF; fi
if [ -n "$REF" ] && { [ ! -f "$ref" ] || [ "$(basename "$ref")" != reference.exr ] || [ ! -f "$refdir/reference.txt" ]; }; then
  [ -f "$ref" ] || { echo "bench_relmse: REF: $ref not found" >&2; exit 2; }
  log "using the reference $ref (its own error unknown: no reference.txt of this script beside it)"
  "$CLPT_DIFF" --json "$ref" "$ref" > "$rundir/reference-self.json"
  printf 'spp=%s\nseconds=\nfloor=\nintegrator=%s\n' "$(json "$rundir/reference-self.json" 'j["image"]["spp"]')" \
    "(integrator not known: REF)" > "$rundir/reference.txt"
  refinfo=$rundir/reference.txt
elif [ -f "$ref" ] && [ -f "$refdir/reference.txt" ]; then
  log "reusing the reference $ref"
else
  rm -f "$ref" "$refdir/reference.txt"
  if [ -n "$oiiotool" ]; then
    # An earlier two-part reference of 2 x part_spp holds parts 1 and 2 as its halves.
    halves=$BENCH_DIR/$name/ref-$(ref_key $((2 * part_spp)) 2)
    mkdir -p "$partdir"
    secs=0 parts=()
    for ((k = 0; k < REF_PARTS; k++)); do
      seed=$((1000001 + k)) part=$partdir/part-$((1000001 + k))
      if [ ! -f "$part.exr" ] && [ $k -lt 2 ] && [ -f "$halves/half$k.exr" ] && [ -f "$halves/half$k.json" ]; then
        cp "$halves/half$k.exr" "$part.tmp.exr" && cp "$halves/half$k.json" "$part.json" && mv "$part.tmp.exr" "$part.exr"
      fi
      if [ -f "$part.exr" ] && [ -f "$part.json" ]; then
        log "reference part $((k + 1)) of $REF_PARTS: reusing $part.exr"
      else
        log "reference part $((k + 1)) of $REF_PARTS: $REF_INTEGRATOR, $part_spp spp, $RES, depth $DEPTH, seed $seed ..."
        render "$part.tmp.exr" "$part.json" $(integrator_args "$REF_INTEGRATOR") --spp "$part_spp" --seed "$seed"
        mv "$part.tmp.exr" "$part.exr"
      fi
      secs=$(python3 -c 'import sys; print(float(sys.argv[1]) + float(sys.argv[2]))' "$secs" "$(json "$part.json" 'j["render_seconds"]')")
      parts+=("$part.exr")
    done
    # The reference's own relMSE: two independent parts differ by twice one part's variance,
    # and the mean of n parts has 1/n of it, so floor = (mean relMSE of disjoint pairs) / (2n).
    pairs=()
    for ((k = 0; k + 1 < REF_PARTS; k += 2)); do
      "$CLPT_DIFF" --json "${parts[k]}" "${parts[k + 1]}" > "$refdir/parts-diff-$k.json"
      pairs+=("$(json "$refdir/parts-diff-$k.json" 'j["relmse"]')")
    done
    floor=$(python3 -c 'import sys; v = [float(x) for x in sys.argv[2:] if x]; print(sum(v) / len(v) / (2 * int(sys.argv[1])) if v else "")' "$REF_PARTS" "${pairs[@]}")
    sum=("${parts[0]}")
    for ((k = 1; k < REF_PARTS; k++)); do sum+=("${parts[k]}" --add); done
    "$oiiotool" "${sum[@]}" --mulc "$(python3 -c "print(repr(1.0 / $REF_PARTS))")" \
      --attrib:type=int clpt:spp "$REF_SPP" -d float -o "$refdir/reference.tmp.exr"
    mv "$refdir/reference.tmp.exr" "$ref"
    ref_spp=$REF_SPP
  else
    [ -n "$oiiotool" ] || log "oiiotool not found: one reference render, its own error not estimated"
    log "reference: $REF_INTEGRATOR, $REF_SPP spp, $RES, depth $DEPTH, seed 1000001 ..."
    render "$ref" "$refdir/reference.json" $(integrator_args "$REF_INTEGRATOR") --spp "$REF_SPP" --seed 1000001
    secs=$(json "$refdir/reference.json" 'j["render_seconds"]')
    floor=
    ref_spp=$REF_SPP
  fi
  printf 'spp=%s\nseconds=%s\nfloor=%s\nintegrator=%s\nparts=%s\n' "$ref_spp" "$secs" "$floor" "$REF_INTEGRATOR" "$REF_PARTS" > "$refdir/reference.txt"
fi
refinfo=${refinfo:-$refdir/reference.txt}
ref_spp=$(sed -n 's/^spp=//p' "$refinfo")
ref_secs=$(sed -n 's/^seconds=//p' "$refinfo")
floor=$(sed -n 's/^floor=//p' "$refinfo")
ref_integ=$(sed -n 's/^integrator=//p' "$refinfo")
ref_parts=$(sed -n 's/^parts=//p' "$refinfo")

# ---- timed renders ----------------------------------------------------------------------------
status=0
rows=()
for integ in "${integrators[@]}"; do
  safe=${integ//[^A-Za-z0-9_.-]/_}
  spps=() secss=() rels=() failed=
  for ((r = 0; r < RUNS; r++)); do
    seed=$((SEED + r))
    tag=$safe; [ "$RUNS" -gt 1 ] && tag=$safe-seed$seed
    img=$rundir/$tag.exr stats=$rundir/$tag.json
    log "$integ: $seconds s, $RES, depth $DEPTH, seed $seed ..."
    if render "$img" "$stats" $(integrator_args "$integ") --time "$seconds" --seed "$seed"; then
      rc=0
      "$CLPT_DIFF" --json "$img" "$ref" > "$rundir/$tag.diff.json" || rc=$?
      if [ $rc -ne 0 ]; then failed="clpt-diff failed (exit $rc)"; break; fi
      spps+=("$(json "$stats" 'j["spp"]')")
      secss+=("$(json "$stats" 'j["render_seconds"]')")
      rels+=("$(json "$rundir/$tag.diff.json" 'j["relmse"]')")
    else
      rc=$?
      failed="clpt failed (exit $rc)"
      break
    fi
  done
  if [ -n "$failed" ]; then
    log "$integ: $failed"
    rows+=("$integ|$failed||")
    status=1
  else
    rows+=("$integ|${spps[*]}|${secss[*]}|${rels[*]}")
  fi
done

# ---- table ------------------------------------------------------------------------------------
python3 - "$scene" "$seconds" "$RES" "$DEPTH" "$ref" "$ref_spp" "$ref_secs" "$floor" "$ref_integ" \
  "$RUNS" "${ref_parts:-2}" "${rows[@]}" <<'PY' | tee "$rundir/table.txt"
import math, sys
scene, seconds, res, depth, ref, ref_spp, ref_secs, floor, ref_integ, runs, ref_parts = sys.argv[1:12]
floor = float(floor) if floor else None
runs = int(runs)

def mean(xs):
    return sum(xs) / len(xs)

rows = []
spread = {}  # each integrator's relMSE per run
for r in sys.argv[12:]:
    integ, spp, secs, rel = r.split("|")
    if not secs:  # failed: spp holds the message
        rows.append((integ, spp, None, None))
        continue
    rel_v = [float(x) if x else math.nan for x in rel.split()]
    rows.append((integ, f"{mean([int(x) for x in spp.split()]):.0f}", mean([float(x) for x in secs.split()]),
                 mean(rel_v)))
    spread[integ] = rel_v

def g(x, spec=".4g"):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)

print(f"scene {scene}, {res}, max depth {depth}, {seconds} s per integrator"
      + (f", means over {runs} runs (seeds differ)" if runs > 1 else ""))
print(f"reference {ref}: {ref_integ} {ref_spp} spp"
      + (f", {float(ref_secs):.1f} s" if ref_secs else "") + "; its own relMSE "
      + ((f"~ {floor:.3g} (a quarter of the relMSE between its two halves)" if ref_parts == "2" else
          f"~ {floor:.3g} (from the relMSE between pairs of its {ref_parts} parts)") if floor is not None
         else "not estimated"))
pt = next((r[3] for r in rows if r[0] == "pt" and r[3] is not None and not math.isnan(r[3])), None)
head = f"{'integrator':<12} {'spp':>8} {'seconds':>8} {'relMSE':>11} {'relMSE-ref':>11} {'pt/this':>8} {'pt/this-ref':>11}"
print(head)
print("-" * len(head))
worst = None
for integ, spp, secs, rel in rows:
    if secs is None:
        print(f"{integ:<12} {spp}")
        continue
    net = rel - floor if floor is not None else None
    ratio = pt / rel if pt is not None and rel and rel > 0 else None
    net_pt = pt - floor if pt is not None and floor is not None else None
    net_ratio = net_pt / net if net_pt is not None and net is not None and net > 0 else None
    if floor is not None and rel and rel > 0:
        share = floor / rel
        worst = share if worst is None else max(worst, share)
    print(f"{integ:<12} {spp:>8} {secs:>8.2f} {g(rel):>11} {g(net):>11} {g(ratio, '.3g'):>8} {g(net_ratio, '.3g'):>11}")
if pt is None:
    print("(no pt row: the ratio columns need pt among the integrators)")
if runs > 1:
    # relMSE is heavy-tailed: one run's firefly can carry the mean of a few, so the mean's
    # standard error and the median go beside it.
    print(f"{'integrator':<12} {'relMSE mean':>11} {'std. error':>11} {'median':>11}   per run")
    for integ, v in spread.items():
        ok = [x for x in v if not math.isnan(x)]
        if not ok:
            continue
        m = mean(ok)
        se = math.sqrt(sum((x - m) ** 2 for x in ok) / (len(ok) - 1) / len(ok)) if len(ok) > 1 else math.nan
        med = sorted(ok)[len(ok) // 2] if len(ok) % 2 else 0.5 * sum(sorted(ok)[len(ok) // 2 - 1:len(ok) // 2 + 1])
        print(f"{integ:<12} {g(m):>11} {g(se):>11} {g(med):>11}   " + " ".join(g(x, '.3g') for x in v))
if worst is not None and worst > 0.1:
    print(f"WARNING: the reference's own relMSE is {100 * worst:.0f} % of the smallest relMSE measured; "
          "the figures and ratios are dominated by it: raise REF_SPP")
PY
log "outputs in $rundir"
exit $status
