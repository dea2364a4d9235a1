#!/usr/bin/env python3
"""Proves the vendor compile check can fail: each mutation of the kernels (in a copy) must make
scripts/kernel_compile_check.py fail with the message that names it, and the unmutated copy
must pass. One small program (ao) and the fast targets keep it to seconds.

    scripts/kernel_check/mutation_test.py [--clpt BIN]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECK = os.path.join(ROOT, "scripts", "kernel_compile_check.py")
AO = os.path.join("integrators", "ao.cl")


def c99_inline(kernels):
    """Every `static inline` back to C99's bare `inline`: no external definition."""
    for d, _, files in os.walk(kernels):
        for f in files:
            if f.endswith((".cl", ".h")):
                p = os.path.join(d, f)
                with open(p) as fh:
                    text = fh.read()
                with open(p, "w") as fh:
                    fh.write(re.sub(r"^static inline ", "inline ", text, flags=re.M))


def edit_ao(old, new):
    def apply(kernels):
        p = os.path.join(kernels, AO)
        with open(p) as fh:
            text = fh.read()
        assert old in text, "mutation anchor %r not in %s" % (old, AO)
        with open(p, "w") as fh:
            fh.write(text.replace(old, new, 1))
    return apply


# name, mutation, targets, text the check must print
MUTATIONS = [
    ("C99 inline", c99_inline, "nvptx", "unresolved functions"),
    # 0.1 is no float, so LLVM cannot narrow the product back to float arithmetic
    ("a double literal", edit_ao("? 0.0f : 1.0f;", "? 0.0f : ao->radius * 0.1;"), "amdgcn",
     "computes in double"),
    ("printf", edit_ao("  Hit hit;\n", "  Hit hit;\n  printf(\"%d\", 1);\n"), "amdgcn", "printf"),
    ("__OPENCL_VERSION__ alone", edit_ao("static inline float ao_sample",
                                          "#ifdef __OPENCL_VERSION__\n#endif\nstatic inline float ao_sample"),
     "amdgcn", "__OPENCL_VERSION__ alone"),
    ("a syntax error", edit_ao("++*rays;", "++*rays"), "tgllp", "FAILED"),
]


def check(clpt, kernels, targets):
    p = subprocess.run([sys.executable, CHECK, "--clpt", clpt, "--kernel-dir", kernels,
                        "--programs", "ao", "--targets", targets, "--no-ptxas"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace")
    return p.returncode, p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--clpt", default=os.path.join(ROOT, "build", "clpt"))
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="clpt-compile-mutants-")
    failed = 0
    try:
        base = os.path.join(work, "base")
        shutil.copytree(os.path.join(ROOT, "kernels"), base)
        rc, out = check(args.clpt, base, "nvptx,amdgcn,tgllp")
        print("unmutated: exit %d" % rc)
        if rc != 0:
            print(out)
            failed += 1
        for name, mutate, targets, expected in MUTATIONS:
            kernels = os.path.join(work, re.sub(r"\W+", "_", name))
            shutil.copytree(base, kernels)
            mutate(kernels)
            rc, out = check(args.clpt, kernels, targets)
            caught = rc == 1 and expected in out
            print("%-26s %s: exit %d%s" % (name, targets, rc, "" if caught else "  NOT CAUGHT"))
            if not caught:
                print(out)
                failed += 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d passed, %d failed" % (len(MUTATIONS) + 1 - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
