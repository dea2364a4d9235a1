#!/usr/bin/env bash
# Fuzzes clpt's readers with libFuzzer, ASan and UBSan.
#
#   scripts/fuzz.sh [SECONDS] [TARGET]     default 300 s, target gltf
#
# Targets (tests/fuzz/):
#   gltf   the glTF loader (clpt::load_gltf, .gltf and .glb)
#   file   the other readers: images for --env/--reference/clpt-diff (read_image_channels:
#          .hdr, .exr, .png, .jpg), textures (decode_image, image_header_size: PNG, JPEG,
#          WebP) and checkpoints (read_checkpoint); the input's first byte picks the reader
#
# Builds build-fuzz/TARGET_fuzzer with clang (CLPT_FUZZ=ON). The gltf target is seeded from
# tests/data (the malformed corpus and the valid files), scenes/*.gltf and the small files of
# ../shared/scenes and ../shared/scenes-extensions (Draco, meshopt and quantized geometry,
# WebP images) when that folder exists; the file target from one valid file per reader that
# it writes itself (CLPT_FUZZ_WRITE_SEEDS) and the small PNG, JPEG and WebP textures of
# ../shared. One worker per core (CLPT_FUZZ_JOBS overrides), carrying on after a finding so
# one run can collect several.
#
# Kept between runs, in build-fuzz/ (gltf: corpus/, findings/, fuzz.log; file: corpus-file/,
# findings-file/, fuzz-file.log):
#   corpus      the inputs that reached new code (the next run starts from them)
#   findings    crash-*, leak-*, timeout-*, oom-*: inputs that crashed, tripped a sanitizer,
#               hung (> 10 s), used more than 2 GiB, or (file) made one allocation over
#               256 MiB; reproduce one with build-fuzz/TARGET_fuzzer FINDING
#   fuzz.log    the last run's log (each finding's report with its stack is in it)
# Exits 1 when this run added a finding, 0 otherwise. Needs clang with libFuzzer (Debian 12:
# clang-14 and libclang-rt-14-dev). See docs/robustness.md.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-300}
target=${2:-gltf}
[[ "$seconds" =~ ^[0-9]+$ ]] && [ "$seconds" -gt 0 ] || { echo "usage: $0 [SECONDS] [gltf|file]" >&2; exit 2; }
case "$target" in
  gltf) corpus_dir=corpus findings_dir=findings log_name=fuzz.log
        extra=(-dict=tests/fuzz/gltf.dict) ;;
  file) corpus_dir=corpus-file findings_dir=findings-file log_name=fuzz-file.log
        extra=(-malloc_limit_mb=256) ;;
  *) echo "usage: $0 [SECONDS] [gltf|file]" >&2; exit 2 ;;
esac
jobs=${CLPT_FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
build=build-fuzz

check_dir=$(mktemp -d)
tmp_dir=""
cleanup() { rm -rf "$check_dir" ${tmp_dir:+"$tmp_dir"}; }
trap cleanup EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' \
  >"$check_dir/t.cpp"
if ! command -v clang++ >/dev/null ||
   ! clang++ -fsanitize=fuzzer,address,undefined "$check_dir/t.cpp" -o "$check_dir/t" 2>/dev/null; then
  echo "fuzz.sh: needs clang++ with libFuzzer (Debian 12: apt-get install clang-14 libclang-rt-14-dev)" >&2
  exit 2
fi

CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCLPT_FUZZ=ON -DCLPT_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target "${target}_fuzzer"

# Seeds, rebuilt each run. A .gltf with an external buffer becomes one input: its first
# external buffer URI rewritten to scene.bin, then the separator, then that .bin's bytes (the
# layout tests/fuzz/gltf_fuzzer.cpp splits).
seeds="$build/seeds-$target"
rm -rf "$seeds"
mkdir -p "$seeds" "$build/$corpus_dir" "$build/$findings_dir"
if [ "$target" = file ]; then
  CLPT_FUZZ_WRITE_SEEDS="$seeds" "$build/file_fuzzer"
  python3 - "$seeds" ../shared/scenes ../shared/scenes-extensions <<'EOF'
import hashlib, os, sys
out, roots = sys.argv[1], sys.argv[2:]
n = 0
for root in roots:
    if not os.path.isdir(root): continue
    for dirpath, _, files in os.walk(root):
        for name in sorted(files):
            path = os.path.join(dirpath, name)
            if not name.lower().endswith((".png", ".jpg", ".jpeg", ".webp")) or os.path.getsize(path) > 64 * 1024:
                continue
            data = b"\x04" + open(path, "rb").read()  # reader 4: the texture decoder
            with open(os.path.join(out, hashlib.sha1(data).hexdigest()), "wb") as f: f.write(data)
            n += 1
print(f"fuzz.sh: {len(os.listdir(out))} seed inputs in {out} ({n} textures from ../shared)")
EOF
else
python3 - "$seeds" tests/data/malformed tests/data/valid scenes ../shared/scenes ../shared/scenes-extensions <<'EOF'
import hashlib, json, os, sys
out, roots = sys.argv[1], sys.argv[2:]
SEP = b"\n#clpt-fuzz-bin#\n"
LIMIT = 256 * 1024
n = 0
def emit(data):
    global n
    if len(data) > LIMIT: return
    with open(os.path.join(out, hashlib.sha1(data).hexdigest()), "wb") as f: f.write(data)
    n += 1
for root in roots:
    if not os.path.isdir(root): continue
    for dirpath, _, files in os.walk(root):
        for name in sorted(files):
            path = os.path.join(dirpath, name)
            if not name.endswith((".gltf", ".glb")) or os.path.getsize(path) > LIMIT: continue
            data = open(path, "rb").read()
            emit(data)
            if not name.endswith(".gltf"): continue
            try: doc = json.loads(data)
            except Exception: continue
            if not isinstance(doc, dict): continue
            for buf in doc.get("buffers", []) if isinstance(doc.get("buffers"), list) else []:
                uri = buf.get("uri") if isinstance(buf, dict) else None
                if not isinstance(uri, str) or uri.startswith("data:"): continue
                binpath = os.path.join(dirpath, uri)
                if not os.path.isfile(binpath) or os.path.getsize(binpath) > LIMIT: break
                buf["uri"] = "scene.bin"
                emit(json.dumps(doc).encode() + SEP + open(binpath, "rb").read())
                break
print(f"fuzz.sh: {n} seed inputs in {out}")
EOF
fi

before=$(ls "$build/$findings_dir" | wc -l)
tmp_dir=$(mktemp -d)  # the fuzzer's own scene folders go here (TMPDIR) and are removed after
echo "fuzz.sh: fuzzing for $seconds s with $jobs worker(s); log in $build/$log_name"
set +e
TMPDIR="$tmp_dir" ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:symbolize=1" \
UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
"$build/${target}_fuzzer" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -max_total_time="$seconds" -timeout=10 -report_slow_units=100000 -rss_limit_mb=2048 \
  "${extra[@]}" \
  -artifact_prefix="$build/$findings_dir/" "$build/$corpus_dir" "$seeds" >"$build/$log_name" 2>&1
status=$?
set -e
tail -n 5 "$build/$log_name"
after=$(ls "$build/$findings_dir" | wc -l)
echo "fuzz.sh: libFuzzer exit status $status; corpus $(ls "$build/$corpus_dir" | wc -l) inputs;" \
     "findings: $after in $build/$findings_dir ($((after - before)) new in this run)"
if [ "$after" -gt "$before" ]; then
  ls -t "$build/$findings_dir" | head -n $((after - before)) | sed "s|^|  $build/$findings_dir/|"
  exit 1
fi
