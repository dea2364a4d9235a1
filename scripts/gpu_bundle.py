#!/usr/bin/env python3
"""Pack a built clpt into a folder that runs on a machine without its libraries (issue 19).

    scripts/gpu_bundle.py [--build DIR] [--out DIR]

A lent GPU machine has the vendor's OpenCL driver and little else. Until session 43 clpt's
shared libraries from Debian weighed 368 MB, nearly all of it pulled in by OpenImageIO's format
plugins (video through ffmpeg, DICOM, OpenVDB, OpenCV, GDAL behind them); clpt now reads and
writes images through OpenEXR, libpng, libjpeg and libwebp directly, and only the test binary
clpt_io_tests (not bundled) links OpenImageIO, so the stubs below are for whatever of those
libraries a bundled binary still loads. The bundle holds

    DIR/clpt, DIR/clpt-raybench,
    DIR/tests/clpt_tests                the binaries, unchanged;
    DIR/CMakeCache.txt                  the source path the tests were built from;
    DIR/lib/                            every shared library they load except glibc's, where
                                        those of the unused plugins are replaced by stubs.

A stub is a small library with the same soname and symbol versions that defines exactly the
symbols the real libraries import from it (read from their dynamic symbol tables: OpenImageIO
is linked with BIND_NOW, so each must resolve at start-up), each function returning the address of
zeroed memory (an empty string to a version query), each object zero-filled. A plugin that reached a stub would misbehave, so the bundle is for the GPU
check's renders and tests only, not for distribution. Run scripts/gpu-check.sh --build DIR:
it puts DIR/lib on LD_LIBRARY_PATH. The script checks that nothing but glibc resolves from
outside the bundle and prints the bundle's size.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

# glibc's own libraries: the target machine has a newer glibc; never carry these.
GLIBC = re.compile(r"^(libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl|"
                   r"ld-linux-x86-64)\.so")
# OpenImageIO's plugins that clpt never uses, and the libraries behind them (none of them
# is loaded by a bundled binary since session 43; kept for a build that still links it).
STUB = re.compile(r"^lib(opencv_|dcm|oflog|ofstd|av(codec|format|util|device|filter)|swscale|"
                  r"swresample|heif|openvdb|raw_r|tbb|boost_|freetype|gif|openjp2|"
                  r"jxl|Ptex|squish)")  # not webp: clpt decodes EXT_texture_webp with it


def run(*cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def ldd(path, env=None):
    """soname -> resolved path (None when not found) for path's whole closure."""
    out = subprocess.run(["ldd", path], capture_output=True, text=True, env=env).stdout
    libs = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\S+) => (\S+|not found)", line)
        if m:
            libs[m.group(1)] = None if m.group(2) == "not found" else m.group(2)
    return libs


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", run("readelf", "-d", "-W", path))


def dyn_symbols(path):
    """(defined, undefined): defined = {(name, version or ''): (type, size)}; undefined = set
    of (name, version or '') that are strong references."""
    defined, undefined = {}, set()
    for line in run("readelf", "--dyn-syms", "-W", path).splitlines():
        f = line.split()
        if len(f) < 8 or not f[0].endswith(":") or not f[0][:-1].isdigit():
            continue
        size, typ, bind, ndx, full = f[2], f[3], f[4], f[6], f[7]
        if bind == "LOCAL" or not full:
            continue
        name, _, ver = full.partition("@")
        ver = ver.lstrip("@")
        if ndx == "UND":
            if bind != "WEAK":
                undefined.add((name, ver))
        else:
            defined[(name, ver)] = (typ, int(size, 16) if size.startswith("0x") else int(size))
    return defined, undefined


def versions_needed_from(path):
    """{file soname: set of version names} from path's .gnu.version_r."""
    out, cur = {}, None
    for line in run("readelf", "-V", "-W", path).splitlines():
        m = re.search(r"File: (\S+)", line)
        if m:
            cur = out.setdefault(m.group(1), set())
            continue
        m = re.search(r"Name: (\S+)\s+Flags", line)
        if m and cur is not None:
            cur.add(m.group(1))
    return out


def make_stub(soname, real_path, importers, libdir, workdir):
    """importers: (undefined symbols, versions needed per file) of each real object."""
    defined, _ = dyn_symbols(real_path)
    by_name = {}
    for (name, ver), info in defined.items():
        by_name.setdefault(name, []).append((ver, info))
    wanted = {}  # (name, ver) -> (type, size)
    versions = set()
    for undef, needs in importers:
        versions |= needs.get(soname, set())
        for name, ver in undef:
            for dver, info in by_name.get(name, []):
                if dver == ver or (not ver and dver):
                    wanted[(name, dver)] = info
                    break
    # Functions return the address of zeroed memory: an empty string to the version queries
    # OpenImageIO's plugin catalogue makes at its first use (a null there aborts), a zero to
    # a caller that reads a struct.
    asm = [".bss", ".balign 64", "__stub_zeros: .zero 4096", ".text"]
    nodes = {}
    for (name, ver), (typ, size) in sorted(wanted.items()):
        if typ in ("TLS", "OBJECT"):
            size = max(size, 8)
            section = '.section .tbss,"awT",@nobits' if typ == "TLS" else ".data"
            asm += [section, ".balign 16", ".globl %s" % name, ".type %s,@object" % name,
                    ".size %s,%d" % (name, size), "%s: .zero %d" % (name, size), ".text"]
        else:
            asm += [".globl %s" % name, ".type %s,@function" % name,
                    "%s: lea __stub_zeros(%%rip), %%rax" % name, "ret"]
        nodes.setdefault(ver, []).append(name)
    for ver in versions:
        nodes.setdefault(ver, [])
    stem = os.path.join(workdir, soname)
    with open(stem + ".s", "w") as f:
        f.write("\n".join(asm) + "\n")
    cmd = ["gcc", "-shared", "-nostdlib", "-o", os.path.join(libdir, soname),
           "-Wl,-soname," + soname, stem + ".s"]
    named = sorted(v for v in nodes if v)
    if named:
        unversioned = nodes.get("", [])
        with open(stem + ".map", "w") as f:
            for j, v in enumerate(named):
                syms = nodes[v] + (unversioned if j == 0 else [])
                f.write("%s {\n  global:\n%s" % (v, "".join("    %s;\n" % s for s in syms)))
                f.write("  local: *;\n};\n" if j == 0 else "};\n")
        cmd.append("-Wl,--version-script=" + stem + ".map")
    subprocess.run(cmd, check=True)
    return len(wanted)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--out", default=os.path.join(root, "gpu-bundle"))
    a = ap.parse_args()
    binaries = {"clpt": os.path.join(a.build, "clpt"),
                "clpt-raybench": os.path.join(a.build, "clpt-raybench"),
                "tests/clpt_tests": os.path.join(a.build, "tests", "clpt_tests")}
    for path in binaries.values():
        if not os.access(path, os.X_OK):
            sys.exit("gpu_bundle: %s is not built" % path)
    shutil.rmtree(a.out, ignore_errors=True)
    libdir = os.path.join(a.out, "lib")
    os.makedirs(os.path.join(a.out, "tests"))
    os.makedirs(libdir)
    for rel, path in binaries.items():
        shutil.copy2(path, os.path.join(a.out, rel))
    with open(os.path.join(a.build, "CMakeCache.txt")) as f:
        home = [l for l in f if l.startswith("CMAKE_HOME_DIRECTORY:INTERNAL=")]
    with open(os.path.join(a.out, "CMakeCache.txt"), "w") as f:
        f.writelines(home)

    # Walk the NEEDED graph from the binaries: real libraries are copied and walked further,
    # stubbed ones end the walk.
    resolved = {}
    for path in binaries.values():
        resolved.update({k: v for k, v in ldd(path).items() if v})
    real, stubbed, todo = [], set(), list(binaries.values())
    seen = set()
    while todo:
        obj = todo.pop()
        for so in needed(obj):
            if so in seen or GLIBC.match(so):
                continue
            seen.add(so)
            if so not in resolved:
                sys.exit("gpu_bundle: %s (needed by %s) is not found" % (so, obj))
            if STUB.match(so):
                stubbed.add(so)
            else:
                real.append((so, resolved[so]))
                todo.append(resolved[so])
    for so, path in real:  # under its soname, the name the loader looks for
        shutil.copy2(path, os.path.join(libdir, so))
    # Each real object's imports, read once for every stub.
    importers = [(dyn_symbols(obj)[1], versions_needed_from(obj))
                 for obj in list(binaries.values()) + [path for _, path in real]]
    count = 0
    with tempfile.TemporaryDirectory() as work:
        for so in sorted(stubbed):
            count += make_stub(so, resolved[so], importers, libdir, work)

    # Everything but glibc must now resolve inside the bundle.
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.abspath(libdir))
    outside = []
    for rel in binaries:
        for so, path in ldd(os.path.join(a.out, rel), env).items():
            if GLIBC.match(so):
                continue
            if not path or not os.path.abspath(path).startswith(os.path.abspath(libdir)):
                outside.append("%s: %s -> %s" % (rel, so, path))
    if outside:
        sys.exit("gpu_bundle: resolves outside the bundle:\n  " + "\n  ".join(outside))
    total = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(a.out) for f in fs)
    print("gpu_bundle: %s: %d libraries, %d stubs (%d symbols), %.1f MB" % (
        a.out, len(real), len(stubbed), count, total / 1e6))


if __name__ == "__main__":
    main()
