#!/usr/bin/env python3
"""The irradiance cache's error split into bias^2 and variance (issue 17; the lecture's
"unbiased vs consistent" slide made runnable; docs/concepts/irradiance-caching.md).

For each case A:RAYS (--ic-error A, --ic-rays RAYS) clpt renders the scene with
--integrator ic under K seeds (each seed builds its own cache). With I_k those images, M their
per-pixel mean and R the reference, per pixel-channel and with clpt's relMSE normalisation
1 / (|R| + 0.01)^2 (host/stats/image_stats.cpp):
    relMSE    mean over k of relMSE(I_k, R): one render's error;
    variance  the seeds' spread, sum_k (I_k - M)^2 / (K - 1), normalised and averaged: the
              part that averaging renders (or more samples) removes;
    bias^2    relMSE(M, R) - variance / K: what stays, the interpolation error (and the
              reference's own error, which this does not remove).
relMSE = bias^2 + variance in expectation. Needs oiiotool (scripts/exr_pixels.py).

  scripts/ic_bias_variance.py --reference REF.exr [--clpt build/clpt] [--scene S]
      [--resolution 128x128] [--spp 256] [--seeds 6] [--cases 0.4:256,0.2:256,0.1:256]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_pixels import load_rgb  # noqa: E402

OFFSET = 0.01  # kRelMseOffset


def rel(v, r):
    return (v - r) ** 2 / (abs(r) + OFFSET) ** 2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--clpt", default=os.path.join(root, "build", "clpt"))
    ap.add_argument("--scene", default=os.path.join(root, "scenes", "cornell_box.gltf"))
    ap.add_argument("--reference", required=True)
    ap.add_argument("--resolution", default="128x128")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--cases", default="0.4:256,0.2:256,0.1:256")
    args = ap.parse_args()
    if args.seeds < 2:
        sys.exit("--seeds must be at least 2")
    ref = load_rgb(args.reference)
    keys = sorted(ref)
    print(f"scene {args.scene}, {args.resolution}, {args.spp} spp, {args.seeds} seeds, "
          f"reference {args.reference}")
    print(f"{'a':>5} {'rays':>6} {'records':>8} {'build s':>8} {'relMSE':>10} {'bias^2':>10} {'variance':>10}")
    with tempfile.TemporaryDirectory() as tmp:
        for case in args.cases.split(","):
            a, rays = case.split(":")
            images, records, build = [], [], []
            for k in range(args.seeds):
                out, stats = os.path.join(tmp, f"ic{k}.exr"), os.path.join(tmp, f"ic{k}.json")
                cmd = [args.clpt, args.scene, "--integrator", "ic", "--ic-error", a, "--ic-rays", rays,
                       "--resolution", args.resolution, "--spp", str(args.spp), "--seed", str(k + 1),
                       "-q", "-o", out, "--stats", stats]
                subprocess.run(cmd, check=True)
                images.append(load_rgb(out))
                j = json.load(open(stats))
                records.append(j["ic"]["records"])
                build.append(j["ic"]["build_seconds"])
            K = len(images)
            single = mean_err = var = 0.0
            n = 0
            for p in keys:
                for c in range(3):
                    r = ref[p][c]
                    vals = [img[p][c] for img in images]
                    m = sum(vals) / K
                    norm = (abs(r) + OFFSET) ** 2
                    single += sum(rel(v, r) for v in vals) / K
                    mean_err += rel(m, r)
                    var += sum((v - m) ** 2 for v in vals) / (K - 1) / norm
                    n += 1
            single, mean_err, var = single / n, mean_err / n, var / n
            bias2 = mean_err - var / K
            print(f"{a:>5} {rays:>6} {sum(records) / K:>8.0f} {sum(build) / K:>8.2f} "
                  f"{single:>10.3g} {bias2:>10.3g} {var:>10.3g}")


if __name__ == "__main__":
    main()
