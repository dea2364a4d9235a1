#!/usr/bin/env bash
# Runs every integrator's smallest render (the Cornell box, 8x8, one sample per pixel, small
# photon maps and Metropolis bootstraps) on Oclgrind's simulated device, whose memory checks
# report every out-of-bounds read or write of a kernel, so such a bug is found here and not on
# a user's GPU (issue 19). Any message Oclgrind logs fails the check; the log is printed.
#
#   scripts/oclgrind-check.sh [--clpt BIN] [--kernel-dir DIR] [INTEGRATOR...]
#   scripts/oclgrind-check.sh --self-test [--clpt BIN]
#
# --self-test proves the check can fail: ao's kernel, in a copy of the kernels, writes one
# float4 past the film, and the check must fail on it naming an invalid write.
#
# Oclgrind 21.10 (Debian 12) stops at clCreateKernel with "Undefined external function:
# llvm.experimental.noalias.scope.decl" on clpt's programs as they are built for devices: the
# declaration is what LLVM leaves where it inlines a function returning a struct. It is built
# here with -cl-opt-disable and CLPT_NO_ALWAYS_INLINE (kernels/bvh/intersect.cl), so nothing is
# inlined and no declaration is left: the same source, unoptimised. Oclgrind's --uninitialized
# check is not used: it counts a buffer cleared with clEnqueueFillBuffer (every film) as
# uninitialised and reports each read of it.
# Exit status: 0 clean, 1 a finding or a failed render, 2 oclgrind missing.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
clpt="$root/build/clpt" kdir=() self_test=0
while [ $# -gt 0 ]; do
  case "$1" in
    --clpt) clpt="$2"; shift 2 ;;
    --kernel-dir) kdir=(--kernel-dir "$2"); shift 2 ;;
    --self-test) self_test=1; shift ;;
    -*) sed -n '2,22p' "$0" >&2; exit 2 ;;
    *) break ;;
  esac
done
command -v oclgrind >/dev/null || {
  echo "oclgrind-check: oclgrind is not installed (Debian package oclgrind; scripts/install-deps.sh)" >&2
  exit 2; }
if [ "$self_test" = 1 ]; then
  mutant=$(mktemp -d)
  cp -r "$root/kernels" "$mutant/kernels"
  anchor='  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);'
  grep -qF "$anchor" "$mutant/kernels/integrators/ao.cl" || {
    echo "oclgrind-check: self-test anchor not found in ao.cl" >&2; rm -rf "$mutant"; exit 1; }
  sed -i "s|^$anchor|  film_sum[params->width * params->height + pixel] = (float4)(0.0f);\n$anchor|" \
    "$mutant/kernels/integrators/ao.cl"
  out=$("$0" --clpt "$clpt" --kernel-dir "$mutant/kernels" ao 2>&1)
  rc=$?
  rm -rf "$mutant"
  if [ $rc -eq 1 ] && grep -q "Invalid write" <<<"$out"; then
    echo "oclgrind-check: self-test: the planted out-of-bounds write was caught"
    echo "1 passed, 0 failed"
    exit 0
  fi
  echo "$out"
  echo "oclgrind-check: self-test: the planted out-of-bounds write was NOT caught (exit $rc)"
  echo "0 passed, 1 failed"
  exit 1
fi
integrators=("$@")
[ ${#integrators[@]} -gt 0 ] || integrators=(pt direct ao indirect1 lt bdpt pm sppm vcm mlt ic)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=()
for integ in "${integrators[@]}"; do
  extra=()
  case "$integ" in
    pm) extra=(--photons 2000 --caustic-photons 2000 --final-gather 2) ;;
    sppm) extra=(--photons 500) ;;
    mlt) extra=(--mlt-bootstrap 256 --mlt-chains 64) ;;
    ic) extra=(--ic-rays 16) ;;
    indirect1) extra=(--indirect surface) ;;
  esac
  log="$work/$integ.log"
  start=$(date +%s.%N)
  CLPT_CACHE_DIR="$work/cache" timeout 600 oclgrind --log "$log" --max-errors 20 \
    --build-options "-cl-opt-disable -DCLPT_NO_ALWAYS_INLINE" \
    "$clpt" "${kdir[@]}" --device Oclgrind -q "$root/scenes/cornell_box.gltf" \
    --integrator "$integ" --spp 1 --resolution 8x8 -o "$work/$integ.exr" "${extra[@]}" \
    >"$work/$integ.out" 2>&1
  rc=$?
  secs=$(echo "$(date +%s.%N) - $start" | bc)
  if [ $rc -ne 0 ] || [ -s "$log" ] || [ -s "$work/$integ.out" ]; then
    failed+=("$integ")
    printf '%-10s FAILED (exit %d, %.1f s)\n' "$integ" "$rc" "$secs"
    cat "$work/$integ.out" "$log" 2>/dev/null | head -n 60
  else
    printf '%-10s clean (%.1f s)\n' "$integ" "$secs"
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "oclgrind-check: ${#failed[@]} of ${#integrators[@]} failed: ${failed[*]}"
  exit 1
fi
echo "oclgrind-check: ${#integrators[@]} integrators clean"
