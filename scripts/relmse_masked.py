#!/usr/bin/env python3
"""relMSE of a bench_relmse.sh run inside and outside a pixel mask.

usage: scripts/relmse_masked.py RUN_DIR REFERENCE.exr MASK.exr

For every <integrator>-seed<N>.exr in RUN_DIR (scripts/bench_relmse.sh), prints relMSE
against REFERENCE (the same measure as clpt-diff: mean over pixel-channels of
(v - r)^2 / (|r| + 0.01)^2) over all pixels, over the pixels where MASK's red channel is 0,
and over those where it is not, then per integrator the mean over the runs (seeds), its
standard error and the median. Used for the caustic scene,
whose bdpt reference has almost none of the light seen through the glass sphere (docs/BENCHMARKS.md):
the mask is the sphere, rendered as the only emitter at --max-depth 0. Needs oiiotool.
"""
import glob
import math
import os
import statistics
import sys

from exr_pixels import load_rgb as load


def rel_mse(image, ref, keep):
    total, n = 0.0, 0
    for key, r in ref.items():
        if keep(key):
            for v, rc in zip(image[key], r):
                total += (v - rc) ** 2 / (abs(rc) + 0.01) ** 2
                n += 1
    return total / n if n else float("nan")


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    run, ref, mask = sys.argv[1], load(sys.argv[2]), load(sys.argv[3])
    outside = lambda k: mask[k][0] == 0
    inside = lambda k: mask[k][0] != 0
    per = {}
    for path in sorted(glob.glob(os.path.join(run, "*-seed*.exr"))):
        name = os.path.basename(path).split("-seed")[0]
        image = load(path)
        row = (rel_mse(image, ref, lambda k: True), rel_mse(image, ref, outside),
               rel_mse(image, ref, inside))
        per.setdefault(name, []).append(row)
        print("%-24s all %10.4g   outside mask %10.4g   inside mask %10.4g" % ((os.path.basename(path),) + row))
    # relMSE over a few seeds is heavy-tailed (one firefly can carry a run's whole figure):
    # the mean with its standard error, and the median beside it.
    for name, rows in per.items():
        n = len(rows)
        mean = [sum(r[i] for r in rows) / n for i in range(3)]
        se = [math.sqrt(sum((r[i] - mean[i]) ** 2 for r in rows) / (n - 1) / n) if n > 1
              else float("nan") for i in range(3)]
        med = [statistics.median(r[i] for r in rows) for i in range(3)]
        print("%-6s mean of %d: all %10.4g   outside mask %10.4g   inside mask %10.4g"
              % (name, n, *mean))
        print("%-6s std. error:  all %10.4g   outside mask %10.4g   inside mask %10.4g"
              % (name, *se))
        print("%-6s median:      all %10.4g   outside mask %10.4g   inside mask %10.4g"
              % (name, *med))


if __name__ == "__main__":
    main()
