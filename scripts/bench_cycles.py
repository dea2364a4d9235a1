#!/usr/bin/env python3
"""clpt against Blender Cycles (CPU) on the same scene, side by side (issue 21).

    scripts/bench_cycles.py [--pairs N] [--spp N] [--size WxH] [--bounces B] [--out DIR]
                            [--clpt BIN] [--clpt-diff BIN] [SCENE ...]

For each scene (default: scenes/cornell_box.gltf) it renders N alternating pairs, clpt then
Cycles, with the same resolution, samples per pixel, pixel filter (a one-pixel box) and path
length: Cycles' B bounces are clpt's --max-depth B + 1 (clpt counts direct light as bounce 1,
Cycles as bounce 0). Times compared are each renderer's own render time: clpt's
`render_seconds` from --stats (passes only: no start-up, scene load or kernel build), Cycles'
`cycles_render_s` from its EXR metadata (path tracing only: no import, sync or BVH build).
Prints every pair, the medians and their ratio (Cycles / clpt: above 1, clpt is faster), and
each image's mean (the two must agree within noise for the times to mean anything).

Cycles comes from Debian's `blender` package (`apt-get install blender python3-numpy`), run by
../shared/tools/cycles/run_cycles.py (glTF importer, Lambert where the file asks for it,
punctual lights as glTF defines them; its README says what it matches and how). Run it on an
otherwise idle machine: both renderers use every core.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RUNNER = os.path.join(ROOT, "..", "shared", "tools", "cycles", "run_cycles.py")


def image_mean(clpt_diff, path):
    """The image's mean over pixels and RGB, from clpt-diff --json against itself."""
    out = subprocess.run([clpt_diff, "--json", path, path], capture_output=True, text=True,
                         check=True).stdout
    return float(json.loads(out)["image"]["mean"])


def cycles_twin(scene, out_dir):
    """Blender 3.4's glTF importer reads KHR_materials_specular's specularColorFactor but not
    specularFactor, so a material that is Lambertian for clpt through specularFactor 0 reaches
    Cycles as a Principled BSDF with specular 0.5 (the runner then keeps it Principled, Burley
    diffuse and a specular lobe). The twin adds specularColorFactor 0 to such materials, which
    changes nothing for clpt (specular times 0) and lets the runner make them Lambertian.
    Binary .glb files and scenes whose files are not all embedded (data: URIs) are used as
    they are."""
    if not scene.endswith(".gltf"):
        return scene, 0
    with open(scene) as f:
        doc = json.load(f)
    uris = [b.get("uri", "") for b in doc.get("buffers", [])] + [i.get("uri", "") for i in doc.get("images", [])]
    if any(u and not u.startswith("data:") for u in uris):
        return scene, 0
    changed = 0
    for m in doc.get("materials", []):
        spec = m.get("extensions", {}).get("KHR_materials_specular")
        if spec is not None and spec.get("specularFactor", 1.0) == 0.0 and "specularColorFactor" not in spec:
            spec["specularColorFactor"] = [0.0, 0.0, 0.0]
            changed += 1
    if not changed:
        return scene, 0
    twin = os.path.join(out_dir, os.path.splitext(os.path.basename(scene))[0] + "-cycles-twin.gltf")
    with open(twin, "w") as f:
        json.dump(doc, f)
    return twin, changed


def render_clpt(args, scene, out):
    stats = out + ".json"
    cmd = [args.clpt, scene, "--device", "pocl", "-q", "--integrator", "pt",
           "--resolution", f"{args.width}x{args.height}", "--spp", str(args.spp),
           "--max-depth", str(args.bounces + 1), "--filter", "box", "--stats", stats, "-o", out]
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)["render_seconds"], " ".join(cmd)


def render_cycles(args, scene, out):
    cmd = ["/usr/bin/python3", RUNNER, scene, out, str(args.spp), str(args.width),
           str(args.height), "--max-bounces", str(args.bounces), "--filter", "BOX",
           "--filter-width", "1.0"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.splitext(out)[0] + ".json") as f:
        return json.load(f)["cycles_render_s"], " ".join(cmd)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", default=[os.path.join(ROOT, "scenes", "cornell_box.gltf")])
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--bounces", type=int, default=8, help="Cycles' bounces (clpt: --max-depth B+1)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench-out", "cycles"))
    ap.add_argument("--clpt", default=os.path.join(ROOT, "build", "clpt"))
    ap.add_argument("--clpt-diff", default=os.path.join(ROOT, "build", "clpt-diff"))
    args = ap.parse_args()
    args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    if not shutil.which("blender"):
        raise SystemExit("bench_cycles: no `blender` on PATH (Debian: apt-get install blender python3-numpy)")
    if not os.path.exists(RUNNER):
        raise SystemExit(f"bench_cycles: {RUNNER} is missing (../shared beside the checkout)")
    os.makedirs(args.out, exist_ok=True)
    print(f"# {args.width}x{args.height}, {args.spp} spp, Cycles {args.bounces} bounces = clpt "
          f"--max-depth {args.bounces + 1}, box filter 1 px, {args.pairs} alternating pairs")
    for scene in args.scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        twin, changed = cycles_twin(scene, args.out)
        if changed:
            print(f"{name}: Cycles renders {twin} ({changed} materials with specularFactor 0 given "
                  "specularColorFactor 0, which Blender 3.4's importer reads)")
        times = {"clpt": [], "cycles": []}
        commands = {}
        for i in range(args.pairs):
            t, commands["clpt"] = render_clpt(args, scene, os.path.join(args.out, f"{name}-clpt-{i}.exr"))
            times["clpt"].append(t)
            t, commands["cycles"] = render_cycles(args, twin, os.path.join(args.out, f"{name}-cycles-{i}.exr"))
            times["cycles"].append(t)
            print(f"{name} pair {i + 1}: clpt {times['clpt'][-1]:.3f} s, Cycles {times['cycles'][-1]:.3f} s")
        m_clpt, m_cycles = statistics.median(times["clpt"]), statistics.median(times["cycles"])
        mean_clpt = image_mean(args.clpt_diff, os.path.join(args.out, f"{name}-clpt-0.exr"))
        mean_cycles = image_mean(args.clpt_diff, os.path.join(args.out, f"{name}-cycles-0.exr"))
        print(f"{name}: median clpt {m_clpt:.3f} s, Cycles {m_cycles:.3f} s, Cycles / clpt "
              f"{m_cycles / m_clpt:.3f}; image means clpt {mean_clpt:.5f}, Cycles {mean_cycles:.5f} "
              f"(ratio {mean_clpt / mean_cycles:.4f})")
        for who in ("clpt", "cycles"):
            print(f"  {who}: {commands[who]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
