#!/usr/bin/env python3
"""Renders many small images with clpt and reports the ones that went wrong: a crash, a hang, an
exit status that is not a clear refusal, or samples dropped for being NaN or infinite.

    scripts/render_sweep.py assets  [--clpt BIN] [--shared DIR] [--integrators LIST]
    scripts/render_sweep.py options [--clpt BIN] [--scene FILE]

assets   every .gltf/.glb under ../shared/scenes and ../shared/scenes-extensions (or --shared)
         with every integrator but pt and ao (the suite's Conformance test renders each file
         with those two, and with one of the others in turn), 24x24, 4 spp: about 500
         renders, 10 minutes on 2 cores.
options  the Cornell box (or --scene) with each integrator under every sampler and pixel
         filter, a thin lens, depths 0 and 1, an environment map (rendered first from the scene
         itself), a constant background, and pt under each of its estimator options: about 240
         renders, 1 minute.

A render counts as refused when clpt exits 1 (usage) or 2 (bad input) with a one-line
message naming what it refuses (an unsupported texture, an option that does not apply); those
are listed apart and are not failures. Exit status: 0 when nothing failed, 1 otherwise.
Python 3 standard library only.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Settings that keep each integrator's start-up small at these sizes.
SMALL = {
    "pm": ["--photons", "3000", "--caustic-photons", "3000", "--final-gather", "2"],
    "mlt": ["--mlt-bootstrap", "2000"],
    "ic": ["--ic-rays", "16"],
    "vcm": ["--vcm-light-paths", "1"],
}


def implemented_integrators(clpt):
    """The integrators clpt implements, in its --help order (the integrator table's rows)."""
    text = subprocess.run([clpt, "--help"], capture_output=True, text=True, check=True).stdout
    m = re.search(r"\(implemented: ([^)]*)\)", text)
    if not m:
        sys.exit("render_sweep: %s --help names no implemented integrators" % clpt)
    return [name.strip() for name in m.group(1).split(",")]


def render(clpt, scene, integrator, extra, work, size="24x24", spp="4"):
    """(status, dropped samples or None, stderr's first line). status: 'ok', 'refused',
    'timeout' or 'exit N'."""
    out, stats = os.path.join(work, "out.exr"), os.path.join(work, "stats.json")
    if os.path.exists(stats):
        os.remove(stats)
    cmd = [clpt, scene, "-q", "--integrator", integrator, "--resolution", size, "--spp", spp,
           "-o", out, "--stats", stats] + SMALL.get(integrator, []) + extra
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    except subprocess.TimeoutExpired:
        return "timeout", None, ""
    first = (p.stderr.strip().splitlines() or [""])[0]
    if p.returncode in (1, 2) and first.startswith("error:") and "\n" not in p.stderr.strip():
        return "refused", None, first
    if p.returncode != 0:
        return "exit %d" % p.returncode, None, first
    try:
        with open(stats) as f:
            return "ok", json.load(f).get("dropped_samples"), first
    except (OSError, ValueError):
        return "no stats", None, first


def asset_jobs(args):
    shared = args.shared or os.path.join(ROOT, "..", "shared")
    files = []
    for sub in ("scenes", "scenes-extensions"):
        for dirpath, _, names in os.walk(os.path.join(shared, sub)):
            files += [os.path.join(dirpath, n) for n in names if n.endswith((".gltf", ".glb"))]
    if not files:
        sys.exit("render_sweep: no glTF files under %s/scenes*" % shared)
    others = [i for i in implemented_integrators(args.clpt) if i not in ("pt", "ao")]
    integrators = args.integrators.split(",") if args.integrators else others
    return [(f, i, []) for f in sorted(files) for i in integrators]


def option_jobs(args, work):
    scene = args.scene or os.path.join(ROOT, "scenes", "cornell_box.gltf")
    env = os.path.join(work, "env.exr")
    subprocess.run([args.clpt, scene, "-q", "--resolution", "32x16", "--spp", "16", "-o", env],
                   check=True)
    jobs = []
    for it in implemented_integrators(args.clpt):
        for sampler in ("independent", "stratified", "lhs", "sobol"):
            for flt in ("box", "tent", "gaussian", "blackman-harris"):
                jobs.append((scene, it, ["--sampler", sampler, "--filter", flt]))
        for extra in (["--aperture", "0.05"], ["--max-depth", "0"], ["--max-depth", "1"],
                      ["--env", env], ["--background", "0.5,0.5,0.5"]):
            jobs.append((scene, it, extra))
    for extra in (["--direct", "light"], ["--direct", "bsdf"], ["--hemisphere", "cosine"],
                  ["--hemisphere", "uniform"], ["--rr", "fixed:0.3"], ["--light-samples", "3"],
                  ["--branching", "3"], ["--mis", "balance"]):
        jobs.append((scene, "pt", extra))
    return jobs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mode", choices=["assets", "options"])
    ap.add_argument("--clpt", default=os.path.join(ROOT, "build", "clpt"))
    ap.add_argument("--shared", help="the folder holding scenes/ and scenes-extensions/")
    ap.add_argument("--integrators",
                    help="assets: comma-separated [every implemented one but pt and ao]")
    ap.add_argument("--scene", help="options: the scene [scenes/cornell_box.gltf]")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        jobs = asset_jobs(args) if args.mode == "assets" else option_jobs(args, work)
        failed, refused = [], []
        for n, (scene, it, extra) in enumerate(jobs, 1):
            status, dropped, message = render(args.clpt, scene, it, extra, work)
            what = "%s %s %s" % (os.path.relpath(scene), it, " ".join(extra))
            if status == "refused":
                refused.append("%s: %s" % (what, message))
            elif status != "ok" or dropped:
                failed.append("%s: %s, dropped %s %s" % (what, status, dropped, message))
                print("FAILED " + failed[-1], flush=True)
            if n % 50 == 0:
                print("render_sweep: %d of %d" % (n, len(jobs)), flush=True)
    for line in refused:
        print("refused " + line)
    print("render_sweep: %d renders, %d refused clearly, %d failed" %
          (len(jobs), len(refused), len(failed)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
