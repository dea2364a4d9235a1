#!/usr/bin/env bash
# Bit-identity check for refactors: renders a fixed list of small images (every integrator,
# sampler and estimator option, on the bundled scenes and on shared glTF assets with alpha,
# rough glass, volumes, punctual lights and textures) and records the SHA-1 of each image's
# pixels. `check` renders the same list again and names every image whose pixels changed.
#
#   scripts/golden.sh record DIR [--clpt BIN] [--kernel-dir DIR] [--extra "ARGS"]
#   scripts/golden.sh check  DIR [--clpt BIN] [--kernel-dir DIR] [--extra "ARGS"]
#
# DIR holds hashes.txt (one "name sha1" line per image) and the images of the last run.
# --kernel-dir lets a kernel change be checked without rebuilding (clpt --kernel-dir).
# --extra adds clpt options to every render (e.g. a new feature's off switch, to show that
# with it off the images are the old ones).
# Shared assets (../shared beside the checkout) are skipped, with a message, where absent.
# Exit status: 0 all identical (check) or recorded (record), 1 some image changed or failed.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:-}"; dir="${2:-}"
[[ "$mode" == record || "$mode" == check ]] && [[ -n "$dir" ]] || {
  sed -n '2,13p' "$0" >&2; exit 2; }
shift 2
clpt="$root/build/clpt"; kdir=(); extra=
while [[ $# -gt 0 ]]; do
  case "$1" in
    --clpt) clpt="$2"; shift 2 ;;
    --kernel-dir) kdir=(--kernel-dir "$2"); shift 2 ;;
    --extra) extra="$2"; shift 2 ;;
    *) echo "golden: unknown argument $1" >&2; exit 2 ;;
  esac
done
# One PoCL thread unless the caller sets another count: the splatting integrators (lt, bdpt,
# vcm, mlt) add into the film with atomics whose order two threads leave to chance, so their
# float sums changed in the last bits from run to run (sh_irid_bdpt gave a new hash in each of
# three runs with two threads, the same in three with one; session 41).
export POCL_MAX_PTHREAD_COUNT="${POCL_MAX_PTHREAD_COUNT:-1}"
shared="$root/../shared"
mkdir -p "$dir/images"

# name | scene | arguments (every render adds --device pocl -q and the size below)
cases=$(cat <<'EOF'
pt           | scenes/cornell_box.gltf | --integrator pt
pt_strat     | scenes/cornell_box.gltf | --integrator pt --sampler stratified
pt_lhs       | scenes/cornell_box.gltf | --integrator pt --sampler lhs
pt_sobol     | scenes/cornell_box.gltf | --integrator pt --sampler sobol
pt_light     | scenes/cornell_box.gltf | --integrator pt --direct light
pt_bsdf      | scenes/cornell_box.gltf | --integrator pt --direct bsdf
pt_balance   | scenes/cornell_box.gltf | --integrator pt --mis balance --light-samples 3
pt_cosine    | scenes/cornell_box.gltf | --integrator pt --hemisphere cosine
pt_uniform   | scenes/cornell_box.gltf | --integrator pt --hemisphere uniform
pt_rrfixed   | scenes/cornell_box.gltf | --integrator pt --rr fixed:0.3 --rr-depth 1
pt_branch    | scenes/cornell_box.gltf | --integrator pt --branching 3
pt_lens      | scenes/cornell_box.gltf | --integrator pt --aperture 0.05
pt_depth0    | scenes/cornell_box.gltf | --integrator pt --max-depth 0
pt_caustic   | scenes/caustic.gltf     | --integrator pt
pt_furnace   | scenes/furnace.gltf     | --integrator pt
pt_indirect  | scenes/indirect.gltf    | --integrator pt --max-depth 12
direct       | scenes/cornell_box.gltf | --integrator direct
ao           | scenes/cornell_box.gltf | --integrator ao
indirect1_receiver | scenes/cornell_box.gltf | --integrator indirect1
indirect1_source | scenes/indirect.gltf | --integrator indirect1 --indirect source
indirect1_surface | scenes/cornell_box.gltf | --integrator indirect1 --indirect surface
lt           | scenes/cornell_box.gltf | --integrator lt
lt_sobol     | scenes/caustic.gltf     | --integrator lt --sampler sobol
lt_rr        | scenes/cornell_box.gltf | --integrator lt --rr fixed:0.5 --rr-depth 1
lt_indirect  | scenes/indirect.gltf    | --integrator lt
bdpt         | scenes/cornell_box.gltf | --integrator bdpt
bdpt_balance | scenes/cornell_box.gltf | --integrator bdpt --mis balance --sampler sobol
bdpt_caustic | scenes/caustic.gltf     | --integrator bdpt
bdpt_s2t2    | scenes/cornell_box.gltf | --integrator bdpt --bdpt-strategy 2,2
bdpt_unw     | scenes/cornell_box.gltf | --integrator bdpt --bdpt-strategy 1,3 --bdpt-unweighted
bdpt_lvc     | scenes/cornell_box.gltf | --integrator bdpt --bdpt-lvc 3
bdpt_rr      | scenes/indirect.gltf    | --integrator bdpt --rr-depth 1
pm           | scenes/cornell_box.gltf | --integrator pm --photons 20000 --caustic-photons 20000
pm_caustic   | scenes/caustic.gltf     | --integrator pm --photons 20000 --caustic-photons 50000 --final-gather 0
pm_box       | scenes/cornell_box.gltf | --integrator pm --photons 20000 --caustic-photons 20000 --pm-filter box --knn 20
sppm         | scenes/cornell_box.gltf | --integrator sppm
sppm_caustic | scenes/caustic.gltf     | --integrator sppm --sppm-alpha 0.8
mlt          | scenes/cornell_box.gltf | --integrator mlt --mlt-mode pssmlt --mlt-target luminance --mlt-bootstrap 20000
mlt_door     | scenes/door_ajar.gltf   | --integrator mlt --mlt-mode pssmlt --mlt-target luminance --mlt-large-step 0.1 --mlt-sigma 0.05 --mlt-chains 1000
mlt_lens     | scenes/cornell_box.gltf | --integrator mlt --mlt-mode pssmlt --mlt-target luminance --aperture 0.05 --rr fixed:0.3
mmlt         | scenes/cornell_box.gltf | --integrator mlt --mlt-bootstrap 5000
mmlt_caustic | scenes/caustic.gltf     | --integrator mlt --mlt-bootstrap 5000 --mlt-chains 500
mmlt_env     | scenes/cornell_box.gltf | --integrator mlt --mlt-bootstrap 5000 --max-depth 3 --background 0.2,0.3,0.4
ic           | scenes/cornell_box.gltf | --integrator ic
ic_photons   | scenes/cornell_ceiling.gltf | --integrator ic --ic-photons 20000 --ic-rays 64
pm_fgcache   | scenes/caustic.gltf     | --integrator pm --photons 20000 --caustic-photons 50000 --final-gather-cache --ic-rays 64
vcm          | scenes/cornell_box.gltf | --integrator vcm
vcm_caustic  | scenes/caustic.gltf     | --integrator vcm --mis balance
vcm_ppm      | scenes/cornell_box.gltf | --integrator vcm --vcm-mode ppm
vcm_pt       | scenes/indirect.gltf    | --integrator vcm --vcm-mode pt
sh_alpha_pt     | @scenes/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb | --integrator pt --background 1,1,1
sh_alpha_lt     | @scenes/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb | --integrator lt --background 1,1,1
sh_alpha_bdpt   | @scenes/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb | --integrator bdpt --background 1,1,1
sh_alpha_pm     | @scenes/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb | --integrator pm --background 1,1,1 --photons 20000 --caustic-photons 20000
sh_alpha_sppm   | @scenes/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb | --integrator sppm --background 1,1,1
sh_rough_pt     | @scenes/TransmissionRoughnessTest/glTF-Binary/TransmissionRoughnessTest.glb | --integrator pt --background 1,1,1
sh_rough_lt     | @scenes/TransmissionRoughnessTest/glTF-Binary/TransmissionRoughnessTest.glb | --integrator lt --background 1,1,1
sh_rough_bdpt   | @scenes/TransmissionRoughnessTest/glTF-Binary/TransmissionRoughnessTest.glb | --integrator bdpt --background 1,1,1
sh_rough_pm     | @scenes/TransmissionRoughnessTest/glTF-Binary/TransmissionRoughnessTest.glb | --integrator pm --background 1,1,1 --photons 20000 --caustic-photons 20000
sh_rough_sppm   | @scenes/TransmissionRoughnessTest/glTF-Binary/TransmissionRoughnessTest.glb | --integrator sppm --background 1,1,1
sh_volume_pt    | @scenes-extensions/AttenuationTest/glTF-Binary/AttenuationTest.glb | --integrator pt --background 1,1,1
sh_volume_lt    | @scenes-extensions/AttenuationTest/glTF-Binary/AttenuationTest.glb | --integrator lt --background 1,1,1
sh_volume_bdpt  | @scenes-extensions/AttenuationTest/glTF-Binary/AttenuationTest.glb | --integrator bdpt --background 1,1,1 --rr-depth 1
sh_volume_pm    | @scenes-extensions/AttenuationTest/glTF-Binary/AttenuationTest.glb | --integrator pm --background 1,1,1 --photons 20000 --caustic-photons 20000
sh_volume_sppm  | @scenes-extensions/AttenuationTest/glTF-Binary/AttenuationTest.glb | --integrator sppm --background 1,1,1
sh_lamp_pt      | @scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf | --integrator pt
sh_lamp_lt      | @scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf | --integrator lt
sh_lamp_bdpt    | @scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf | --integrator bdpt
sh_lamp_sppm    | @scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf | --integrator sppm
sh_spot_bdpt    | @scenes/ShadowsSpot/glTF/shadows-spot.gltf | --integrator bdpt
sh_spec_pt      | @scenes-extensions/SpecularTest/glTF-Binary/SpecularTest.glb | --integrator pt --background 1,1,1
sh_spec_bdpt    | @scenes-extensions/SpecularTest/glTF-Binary/SpecularTest.glb | --integrator bdpt --background 1,1,1
sh_normal_pt    | @scenes/NormalTangentMirrorTest/glTF-Binary/NormalTangentMirrorTest.glb | --integrator pt --background 1,1,1
sh_vcolor_lt    | @scenes/VertexColorTest/glTF-Binary/VertexColorTest.glb | --integrator lt --background 1,1,1
sh_multiuv_pm   | @scenes/MultiUVTest/glTF-Binary/MultiUVTest.glb | --integrator pm --background 1,1,1 --photons 20000 --caustic-photons 20000
sh_coat_pt      | @scenes-extensions/ClearCoatTest/glTF-Binary/ClearCoatTest.glb | --integrator pt --background 1,1,1
sh_irid_pt      | @scenes-extensions/IridescenceSuzanne/glTF-Binary/IridescenceSuzanne.glb | --integrator pt --background 0.6,0.6,0.6
sh_irid_bdpt    | @scenes-extensions/IridescenceLamp/glTF/IridescenceLamp.gltf | --integrator bdpt --background 1,1,1
EOF
)

# Splatting (lt, bdpt) and photon deposits use atomics, whose order depends on how PoCL
# schedules work-groups over threads: one thread makes that order, and the images, repeatable.
export POCL_MAX_PTHREAD_COUNT=1 POCL_MAX_CPU_CU_COUNT=1
status=0; done_count=0; skipped=0
new="$dir/hashes.new"; : > "$new"
while IFS='|' read -r name scene args; do
  name="$(echo "$name" | xargs)"; scene="$(echo "$scene" | xargs)"
  [[ -z "$name" ]] && continue
  if [[ "$scene" == @* ]]; then
    scene="$shared/${scene#@}"
    if [[ ! -f "$scene" ]]; then echo "golden: skip $name ($scene absent)"; skipped=$((skipped+1)); continue; fi
  else
    scene="$root/$scene"
  fi
  out="$dir/images/$name.exr"
  # One pass of the 4 samples (--pass-seconds): pass sizes otherwise follow the clock, and a
  # different split sums the film in another order (last-bit changes on a busy machine).
  # shellcheck disable=SC2086
  if ! "$clpt" --device pocl -q "${kdir[@]}" "$scene" -o "$out" --resolution 48x36 --spp 4 \
      --pass-seconds 1000 $args $extra; then
    echo "golden: $name: render failed"; echo "$name FAILED" >> "$new"; status=1; continue
  fi
  hash=$(oiiotool --hash "$out" | sed -n 's/.*SHA-1: *//p' | head -1)
  echo "$name $hash" >> "$new"
  done_count=$((done_count+1))
done <<< "$cases"

if [[ "$mode" == record ]]; then
  mv "$new" "$dir/hashes.txt"
  echo "golden: recorded $done_count images in $dir ($skipped skipped)"
  exit $status
fi
changed=0
while read -r name hash; do
  old=$(awk -v n="$name" '$1 == n {print $2}' "$dir/hashes.txt")
  if [[ -z "$old" ]]; then echo "golden: $name: not in the record"; changed=$((changed+1));
  elif [[ "$old" != "$hash" ]]; then echo "golden: $name: CHANGED"; changed=$((changed+1)); fi
done < "$new"
echo "golden: $done_count images checked, $changed changed, $skipped skipped"
[[ $changed -eq 0 && $status -eq 0 ]]
