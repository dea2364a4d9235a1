#!/usr/bin/env python3
"""Compiles every clpt kernel program with the GPU vendors' compilers, on a machine without a GPU.

    scripts/kernel_compile_check.py [--clpt BIN] [--kernel-dir DIR] [--targets LIST]
                                    [--programs LIST] [--report FILE] [--keep DIR] [--no-ptxas]
                                    [--no-cache]

The programs are what `clpt --dump-kernels` writes: each resolved source with the exact build
options clpt gives the device (programs.tsv; Intel's targets also get the options clpt adds
for Intel GPUs, its fourth column: the megakernels' -cl-intel-256-GRF-per-thread). Targets (--targets, comma-separated; default all):

  nvptx   NVIDIA: clang-15's OpenCL front end to PTX (nvptx64--nvidiacl), with libclc's
          NVPTX builtins linked in (and kernel_check/nvptx_native.cl before them: six native_
          functions LLVM 15 cannot lower for NVPTX). Where NVIDIA's ptxas is on the PATH or in
          /usr/local/cuda (not a Debian package) and --no-ptxas is not given, the PTX is also
          assembled for sm_90, which gives registers, stack and spills per kernel; without it,
          the PTX's local memory per kernel. NVIDIA's driver compiles the source with its own
          front end, so its figures differ from these.
  amdgcn  AMD: clang-15 to a gfx1030 code object (amdgcn-amd-amdhsa), libclc's amdgcn builtins
          linked in; VGPRs, SGPRs, scratch and occupancy per kernel from LLVM's resource remarks.
  nvinline  (opt-in, not in the default list) nvptx with every call inlined into its kernel,
          as NVIDIA's OpenCL compiler does (clang keeps the large functions out of line): the
          PTX grows several times, and ptxas's time on it is this machine's stand-in for the
          driver's build time on the GPU, which measured 72 s for pt on an H200
          (docs/BENCHMARKS.md); a function marked CLPT_NOINLINE stays out of line in both.
  tgllp   Intel Xe-LP (Tiger Lake), and
  dg2     Intel Xe-HPG (Arc): Intel's offline compiler ocloc (Debian's intel-opencl-icd); SIMD
          width, registers (GRF) and scratch per kernel from the binary's .ze_info, and IGC's
          spill warning.

A program fails a target when the compiler exits non-zero or reports an error, or (clang
targets) when the linked module still calls a function nothing defines (a driver would refuse
to link it) or computes in double. Every program's source is also held to the portability
rules its text shows (docs/ARCHITECTURE.md): no printf, no test of __OPENCL_VERSION__ alone. Every failure prints the compiler's log. Exit status 0 when every program compiles
for every target, 1 when one fails, 2 when a compiler is missing or the dump fails.
--report writes the per-kernel figures as a Markdown table (docs/BENCHMARKS.md quotes them).

A pass is remembered (CLPT_COMPILE_CHECK_CACHE, else $XDG_CACHE_HOME/clpt/compile-check) under a
hash of everything it depends on: this script, the target, the compilers' versions and
packages, the options and the source. The same program is then not compiled again until one of
those changes (Intel's compiler takes minutes a target); a failure is never remembered.
--no-cache compiles everything.
"""
import argparse
import hashlib
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIBCLC = "/usr/lib/clc"
TARGETS = ["nvptx", "amdgcn", "tgllp", "dg2"]
# Opt-in targets (named in --targets only): nvinline is nvptx with every call inlined.
EXTRA_TARGETS = ["nvinline"]
NVIDIA_TARGETS = ("nvptx", "nvinline")  # clang to PTX, then ptxas where it is installed
INTEL_TARGETS = ("tgllp", "dg2")  # ocloc, with programs.tsv's Intel GPU options
# clang's inliner threshold that inlines every call it may, as NVIDIA's OpenCL compiler does.
INLINE_ALL = ["-mllvm", "-inline-threshold=100000"]
PACKAGES = {"clang": "clang-15", "libclc": "libclc-15", "ocloc": "intel-opencl-icd"}


def find_clang():
    for name in ("clang-15", "clang"):
        path = shutil.which(name)
        if path:
            return path
    return None


def find_ptxas():
    return shutil.which("ptxas") or next(
        (p for p in ("/usr/local/cuda/bin/ptxas",) if os.access(p, os.X_OK)), None)


def run(cmd, cwd=None):
    t0 = time.monotonic()
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace")
    return p.returncode, p.stdout, time.monotonic() - t0


def read_programs(dump_dir):
    programs = []
    with open(os.path.join(dump_dir, "programs.tsv")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            fields = line.rstrip("\n").split("\t")
            name, entry, options = fields[:3]
            intel = fields[3] if len(fields) > 3 else ""
            programs.append((name, entry, options.split(), intel.split()))
    return programs


def kernel_names(source):
    return re.findall(r"^\s*__kernel\s+void\s+(\w+)\s*\(", source, re.M)


def source_rule_violations(source):
    """docs/ARCHITECTURE.md's portability rules that the source text shows: no printf, and no
    test of __OPENCL_VERSION__ alone (clang's NVPTX and AMDGPU targets define only
    __OPENCL_C_VERSION__)."""
    found = []
    for n, line in enumerate(source.splitlines(), 1):
        code = line.split("//")[0]
        if re.search(r"\bprintf\s*\(", code) and not code.lstrip().startswith("*"):
            found.append("line %d: printf (not every device has it; none may rely on it)" % n)
        if re.match(r"\s*#\s*(if|ifdef|ifndef|elif)\b.*__OPENCL_VERSION__", code) and \
                "__OPENCL_C_VERSION__" not in code:
            found.append("line %d: tests __OPENCL_VERSION__ alone (use CLPT_OPENCL_DEVICE)" % n)
    return found


def unresolved_calls(ll_text):
    """Functions the module declares but does not define, less LLVM's intrinsics."""
    names = re.findall(r"^declare [^@]*@([\w.$]+)\(", ll_text, re.M)
    return [n for n in names if not n.startswith("llvm.")]


def clang_compile(clang, libclc, triple, cpu, src, options, out_base, shim=None, extra=()):
    """Returns (ok, log, seconds, artefact path). shim: bitcode linked before libclc."""
    link = ["-Xclang", "-mlink-builtin-bitcode", "-Xclang", shim] if shim else []
    common = [clang, "-x", "cl", *options, "-Xclang", "-finclude-default-header", "-O3",
              "-target", triple, *link, "-Xclang", "-mlink-builtin-bitcode", "-Xclang", libclc,
              "-Wno-linker-warnings", *extra]
    if cpu:
        common += ["-mcpu=" + cpu]
    if triple.startswith("amdgcn"):
        common += ["-nogpulib"]
    rc, log, secs = run(common + ["-emit-llvm", "-S", src, "-o", out_base + ".ll"])
    if rc != 0 or " error:" in log or log.startswith("error:"):
        return False, log, secs, None
    with open(out_base + ".ll") as f:
        ll = f.read()
    missing = unresolved_calls(ll)
    if missing:
        return False, log + "\nunresolved functions (no definition after linking libclc): " + \
            ", ".join(sorted(set(missing))) + "\n", secs, None
    if re.search(r"\bdouble\b", ll):
        return False, log + "\nthe program computes in double (an unsuffixed literal such as " \
            "0.5 is a double where the device has cl_khr_fp64; write 0.5f): GPUs without " \
            "doubles refuse it and the others run it slowly\n", secs, None
    if triple.startswith("nvptx"):
        out, extra = out_base + ".ptx", ["-S"]
    else:
        out, extra = out_base + ".o", ["-c", "-Rpass-analysis=kernel-resource-usage"]
    # Code generation from the module just written, already optimised and linked with libclc:
    # -disable-llvm-optzns runs the target's code generator at -O3 on it without the
    # optimisation pipeline a second time (what compiling the source again would repeat:
    # about a fifth of the NVPTX and AMDGPU checks' time, for the same code).
    codegen = [clang, "-x", "ir", "-O3", "-target", triple, "-Xclang", "-disable-llvm-optzns",
               "-Wno-linker-warnings"] + (["-mcpu=" + cpu] if cpu else [])
    if triple.startswith("amdgcn"):
        codegen += ["-nogpulib"]
    rc, log2, secs2 = run(codegen + extra + [out_base + ".ll", "-o", out])
    ok = rc == 0 and " error:" not in log2
    return ok, log + log2, secs + secs2, out if ok else None


def ptx_local_bytes(ptx_text):
    """Per .entry: bytes of its __local_depot (the PTX's own stack/local memory)."""
    figures, current = {}, None
    for line in ptx_text.splitlines():
        m = re.search(r"\.entry (\w+)\(", line)
        if m:
            current = m.group(1)
            figures[current] = {"local bytes": 0}
            continue
        m = re.search(r"\.local \.align \d+ \.b8\s+__local_depot\d+\[(\d+)\]", line)
        if m and current:
            figures[current]["local bytes"] = int(m.group(1))
    return figures


def ptxas_figures(ptxas, ptx, kernels):
    rc, log, secs = run([ptxas, "-arch=sm_90", "-v", ptx, "-o", os.devnull])
    if rc != 0:
        return False, log, secs, {}
    figures, current = {}, None
    for line in log.splitlines():
        m = re.search(r"Function properties for (\w+)", line)
        if m:
            current = m.group(1)
            continue
        m = re.search(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads",
                      line)
        if m and current in kernels:
            figures.setdefault(current, {}).update(
                {"stack bytes": int(m.group(1)), "spill stores": int(m.group(2)),
                 "spill loads": int(m.group(3))})
        m = re.search(r"Compiling entry function '(\w+)'", line)
        if m:
            current = m.group(1)
        m = re.search(r"Used (\d+) registers", line)
        if m and current in kernels:
            figures.setdefault(current, {})["registers"] = int(m.group(1))
    return True, log, secs, figures


def amdgpu_figures(log, kernels):
    figures, current = {}, None
    for line in log.splitlines():
        # "FILE:L:C: remark: ..." from source, "remark: <unknown>:0:0: ..." from IR
        m = re.search(r"remark: (?:\S+:\d+:\d+: )?Function Name: (\w+)", line)
        if m:
            current = m.group(1) if m.group(1) in kernels else None
            if current:
                figures[current] = {}
            continue
        m = re.search(r"remark: (?:\S+:\d+:\d+:)?\s+(SGPRs|VGPRs|ScratchSize \[bytes/lane\]|Occupancy \[waves/SIMD\]): "
                      r"(\d+)", line)
        if m and current:
            key = {"SGPRs": "SGPRs", "VGPRs": "VGPRs", "ScratchSize [bytes/lane]": "scratch bytes",
                   "Occupancy [waves/SIMD]": "waves/SIMD"}[m.group(1)]
            figures[current][key] = int(m.group(2))
    return figures


def elf_sections(data):
    """{name: bytes} of a 64-bit little-endian ELF file."""
    if data[:4] != b"\x7fELF":
        return {}
    shoff = struct.unpack_from("<Q", data, 0x28)[0]
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x3A)
    headers = [struct.unpack_from("<IIQQQQ", data, shoff + i * shentsize) for i in range(shnum)]
    strtab = headers[shstrndx]
    sections = {}
    for name, _type, _flags, _addr, offset, size in headers:
        end = data.index(b"\0", strtab[4] + name)
        sections[data[strtab[4] + name:end].decode()] = data[offset:offset + size]
    return sections


def ze_info_figures(binary_path, kernels):
    """Per kernel of `kernels`: simd_size, grf_count and scratch bytes per thread from
    zebin's .ze_info (its top-level 'kernels:' section alone; later sections name them again)."""
    with open(binary_path, "rb") as f:
        info = elf_sections(f.read()).get(".ze_info", b"").decode(errors="replace")
    figures, current, in_kernels, in_buffers = {}, None, False, False
    for line in info.splitlines():
        if re.match(r"\S", line):  # a top-level key
            in_kernels, current = line.startswith("kernels:"), None
            continue
        if not in_kernels:
            continue
        m = re.match(r"  - name:\s+(\w+)", line)
        if m:
            current, in_buffers = (m.group(1) if m.group(1) in kernels else None), False
            if current:
                figures[current] = {"scratch bytes": 0}
            continue
        if current is None:
            continue
        m = re.match(r"\s+(grf_count|simd_size):\s+(\d+)", line)
        if m:
            figures[current]["GRF" if m.group(1) == "grf_count" else "SIMD"] = int(m.group(2))
        if re.match(r"\s+per_thread_memory_buffers:", line):
            in_buffers = True
        m = re.match(r"\s+size:\s+(\d+)", line)
        if in_buffers and m:
            figures[current]["scratch bytes"] += int(m.group(1))
    return figures


def ocloc_compile(ocloc, device, name, src, options, work, kernels):
    out_dir = os.path.join(work, "ocloc-" + device)
    os.makedirs(out_dir, exist_ok=True)
    cmd = [ocloc, "compile", "-file", src, "-device", device, "--format", "zebin",
           "-options", " ".join(options), "-output", name, "-out_dir", out_dir]
    rc, log, secs = run(cmd)
    ok = rc == 0 and "Build succeeded" in log and "error:" not in log
    figures = {}
    if ok:
        bins = [f for f in os.listdir(out_dir) if f.startswith(name + "_") and f.endswith(".bin")]
        if bins:
            figures = ze_info_figures(os.path.join(out_dir, bins[0]), kernels)
        for m in re.finditer(r"kernel (\w+)\s+compiled SIMD(\d+) allocated (\d+) regs and spilled "
                             r"around (\d+)", log):
            if m.group(1) in kernels:
                figures.setdefault(m.group(1), {})["spill"] = int(m.group(4))
        for k in figures:
            figures[k].setdefault("spill", 0)
    return ok, log, secs, figures


def cache_dir():
    d = os.environ.get("CLPT_COMPILE_CHECK_CACHE")
    if d:
        return d
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "clpt", "compile-check")


def cache_key(target, identity, options, source):
    """Everything a result depends on: this script and the nvptx shim, the target, the
    compilers' identities (versions, packages), the options and the source."""
    h = hashlib.sha256()
    for path in (os.path.abspath(__file__),
                 os.path.join(ROOT, "scripts", "kernel_check", "nvptx_native.cl")):
        with open(path, "rb") as f:
            h.update(f.read())
    h.update(json.dumps([target, identity, options]).encode())
    h.update(source.encode())
    return h.hexdigest()


def cache_load(key):
    try:
        with open(os.path.join(cache_dir(), key + ".json")) as f:
            entry = json.load(f)
        return entry if entry.get("ok") is True else None
    except (OSError, ValueError):
        return None


def cache_store(key, seconds, figures):
    d = cache_dir()
    try:
        os.makedirs(d, exist_ok=True)
        tmp = os.path.join(d, "%s.%d.tmp" % (key, os.getpid()))
        with open(tmp, "w") as f:
            json.dump({"ok": True, "seconds": seconds, "figures": figures}, f)
        os.replace(tmp, os.path.join(d, key + ".json"))
    except OSError:
        pass  # an unwritable cache only costs time


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--clpt", default=os.path.join(ROOT, "build", "clpt"))
    ap.add_argument("--kernel-dir", help="kernel sources to dump instead of the built-in ones")
    ap.add_argument("--targets", default=",".join(TARGETS))
    ap.add_argument("--programs", help="comma-separated program names (default: all)")
    ap.add_argument("--report", help="write the per-kernel figures as Markdown to this file")
    ap.add_argument("--keep", help="keep the dump and the compilers' outputs in this folder")
    ap.add_argument("--no-ptxas", action="store_true",
                    help="do not assemble the PTX with ptxas even where it is installed")
    ap.add_argument("--no-cache", action="store_true",
                    help="compile everything, even what an identical earlier run passed")
    args = ap.parse_args()

    targets = [t for t in args.targets.split(",") if t]
    unknown = [t for t in targets if t not in TARGETS + EXTRA_TARGETS]
    if unknown:
        ap.error("unknown target(s) %s; known: %s" % (", ".join(unknown),
                                                      ", ".join(TARGETS + EXTRA_TARGETS)))
    nvidia = [t for t in targets if t in NVIDIA_TARGETS]

    clang, ocloc, ptxas = find_clang(), shutil.which("ocloc"), find_ptxas()
    missing = []
    if nvidia or "amdgcn" in targets:
        if not clang:
            missing.append("clang (Debian package %s)" % PACKAGES["clang"])
        for f in (["nvptx64--nvidiacl.bc"] if nvidia else []) + \
                 (["amdgcn--amdhsa.bc"] if "amdgcn" in targets else []):
            if not os.path.exists(os.path.join(LIBCLC, f)):
                missing.append("%s/%s (Debian package %s)" % (LIBCLC, f, PACKAGES["libclc"]))
    if any(t in ("tgllp", "dg2") for t in targets) and not ocloc:
        missing.append("ocloc (Debian package %s)" % PACKAGES["ocloc"])
    if missing:
        print("kernel_compile_check: missing " + "; ".join(missing) +
              ". scripts/install-deps.sh installs them.", file=sys.stderr)
        return 2

    work = args.keep or tempfile.mkdtemp(prefix="clpt-compile-check-")
    os.makedirs(work, exist_ok=True)
    dump = os.path.join(work, "dump")
    cmd = [args.clpt, "--dump-kernels", dump, "-q"]
    if args.kernel_dir:
        cmd += ["--kernel-dir", args.kernel_dir]
    rc, log, _ = run(cmd)
    if rc != 0:
        print("kernel_compile_check: %s failed (exit %d):\n%s" % (" ".join(cmd), rc, log),
              file=sys.stderr)
        return 2
    programs = read_programs(dump)
    if args.programs:
        wanted = set(args.programs.split(","))
        programs = [p for p in programs if p[0] in wanted]
        if not programs:
            ap.error("no program named %s" % args.programs)

    versions = {}
    clang_version = run([clang, "--version"])[1] if clang else ""
    if clang:
        versions["clang"] = clang_version.splitlines()[0]
    if ocloc:
        m = re.search(r"\d+\.\d+\.\d+(\.\d+)?", run(["dpkg-query", "-W", "-f=${Version}",
                                                      "intel-opencl-icd"])[1])
        versions["ocloc"] = "ocloc (intel-opencl-icd %s)" % (m.group(0) if m else "?")
    if ptxas and nvidia:
        versions["ptxas"] = run([ptxas, "--version"])[1].strip().splitlines()[-1]
    libclc = run(["dpkg-query", "-W", "-f=${Version}", "libclc-15"])[1].strip()

    shim = None
    if nvidia:
        # libclc's NVPTX native_ functions that LLVM 15 cannot lower (kernel_check/nvptx_native.cl).
        shim = os.path.join(work, "nvptx_native.bc")
        rc, log, _ = run([clang, "-x", "cl", "-cl-std=CL1.2", "-Xclang", "-finclude-default-header",
                          "-O3", "-target", "nvptx64--nvidiacl", "-emit-llvm", "-c",
                          os.path.join(ROOT, "scripts", "kernel_check", "nvptx_native.cl"), "-o", shim])
        if rc != 0:
            print("kernel_compile_check: the nvptx shim does not build:\n" + log, file=sys.stderr)
            return 2
    if args.no_ptxas:
        ptxas = None
        versions.pop("ptxas", None)
    identity = {
        "nvptx": [clang_version, libclc,
                  versions.get("ptxas", "no ptxas")],
        "nvinline": [clang_version, libclc, versions.get("ptxas", "no ptxas"), INLINE_ALL],
        "amdgcn": [clang_version, libclc],
        "tgllp": [versions.get("ocloc", "")],
        "dg2": [versions.get("ocloc", "")],
    }

    failures, rows = [], []
    for name, _entry, _options, _intel in programs:
        with open(os.path.join(dump, name + ".cl")) as f:
            violations = source_rule_violations(f.read())
        if violations:
            failures.append(("rules", name))
            print("rules   %-10s FAILED\n  %s" % (name, "\n  ".join(violations)), flush=True)
    for target in targets:
        for name, _entry, options, intel in programs:
            if target in INTEL_TARGETS:
                options = options + intel  # what clpt gives an Intel GPU
            src = os.path.join(dump, name + ".cl")
            with open(src) as f:
                source = f.read()
            kernels = set(kernel_names(source))
            base = os.path.join(work, "%s-%s" % (name, target))
            key = cache_key(target, identity[target], options, source)
            cached = None if args.no_cache else cache_load(key)
            if cached:
                ok, log, secs, figures = True, "", cached["seconds"], cached["figures"]
            elif target in NVIDIA_TARGETS:
                ok, log, secs, out = clang_compile(clang, os.path.join(LIBCLC, "nvptx64--nvidiacl.bc"),
                                                   "nvptx64--nvidiacl", None, src, options, base,
                                                   shim, INLINE_ALL if target == "nvinline" else ())
                figures = {}
                if ok:
                    with open(out) as f:
                        ptx = f.read()
                    figures = ptx_local_bytes(ptx)
                    if target == "nvinline":
                        for k in figures:
                            figures[k]["PTX lines"] = ptx.count("\n")
                    if ptxas:
                        pok, plog, psecs, pfig = ptxas_figures(ptxas, out, set(figures))
                        secs += psecs
                        if not pok:
                            ok, log = False, log + "\nptxas:\n" + plog
                        for k, v in pfig.items():
                            figures.setdefault(k, {}).update(v)
                        if target == "nvinline":
                            for k in figures:
                                figures[k]["ptxas s"] = round(psecs, 1)
            elif target == "amdgcn":
                ok, log, secs, _ = clang_compile(clang, os.path.join(LIBCLC, "amdgcn--amdhsa.bc"),
                                                 "amdgcn-amd-amdhsa", "gfx1030", src, options, base)
                figures = amdgpu_figures(log, kernels) if ok else {}
            else:
                ok, log, secs, figures = ocloc_compile(ocloc, target, name, src, options, work,
                                                       kernels)
            if ok and not cached:
                cache_store(key, secs, figures)
            status = ("ok (cached: this source, options and compiler passed before)" if cached
                      else "ok") if ok else "FAILED"
            print("%-7s %-10s %6.1f s  %s" % (target, name, secs, status), flush=True)
            if not ok:
                failures.append((target, name))
                print("---- %s for %s, options '%s':\n%s\n----" % (target, name, " ".join(options),
                                                                  log.strip()), flush=True)
            for kernel in sorted(figures):
                rows.append((target, name, kernel, figures[kernel]))
            if ok and not figures:
                rows.append((target, name, "(no figures)", {}))
            rows.append((target, name, None, {"seconds": secs}))

    if args.report:
        write_report(args.report, targets, rows, versions, ptxas is not None)
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    print("kernel_compile_check: %d programs x %d targets, %d failed%s" % (
        len(programs), len(targets), len(failures),
        (": " + ", ".join("%s/%s" % f for f in failures)) if failures else ""))
    return 1 if failures else 0


def write_report(path, targets, rows, versions, have_ptxas):
    columns = {
        "nvptx": ["registers", "stack bytes", "spill stores", "spill loads", "local bytes"]
        if have_ptxas else ["local bytes"],
        "nvinline": ["PTX lines", "ptxas s", "registers", "stack bytes", "spill stores",
                     "spill loads"] if have_ptxas else ["PTX lines", "local bytes"],
        "amdgcn": ["VGPRs", "SGPRs", "scratch bytes", "waves/SIMD"],
        "tgllp": ["SIMD", "GRF", "spill", "scratch bytes"],
        "dg2": ["SIMD", "GRF", "spill", "scratch bytes"],
    }
    lines = ["Compilers: " + "; ".join(versions[k] for k in sorted(versions)), ""]
    for target in targets:
        cols = columns[target]
        lines += ["### %s" % target, "",
                  "| program | kernel | " + " | ".join(cols) + " | compile s |",
                  "|---|---|" + "---|" * (len(cols) + 1)]
        seconds = {r[1]: r[3]["seconds"] for r in rows if r[0] == target and r[2] is None}
        for t, name, kernel, fig in rows:
            if t != target or kernel is None:
                continue
            lines.append("| %s | %s | %s | %.1f |" % (
                name, kernel, " | ".join(str(fig.get(c, "")) for c in cols), seconds.get(name, 0)))
        lines.append("")
    with open(path, "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
