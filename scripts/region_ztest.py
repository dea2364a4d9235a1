#!/usr/bin/env python3
"""Compare an image with an unbiased reference over the pixels of a mask, by a z-test.

usage: scripts/region_ztest.py REFERENCE.exr IMAGE.exr MASK.exr

REFERENCE must carry clpt's 'variance' layer (render it with --variance: pt, ao, direct,
pm), the variance of each pixel's mean. Over the pixels where MASK's red channel is not 0,
prints for each channel the sum of IMAGE, the sum of REFERENCE with its standard error
(the square root of the summed variances: pixels are independent), and z = difference /
standard error; then quantiles of the per-pixel z-scores |v - r| / sqrt(var_r) of the
mean of the three channels, and the five pixels that differ most. IMAGE's own noise is not in the standard error, so |z| is an
upper bound on the disagreement the reference alone can explain.

Made for the caustic scene's check (docs/BENCHMARKS.md): whether sppm's light seen through
the glass sphere (E S S D S S L paths, which pt samples only with a large light) agrees with
pt's where pt can find it. Needs oiiotool.
"""
import math
import sys

from exr_pixels import load_channels as load


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    ref, image, mask = (load(p) for p in sys.argv[1:4])
    if "variance.R" not in next(iter(ref.values())):
        sys.exit(f"{sys.argv[1]}: no variance.R/G/B channels (render it with --variance)")
    keys = [k for k, m in mask.items() if m["R"] != 0.0]
    print(f"{len(keys)} of {len(mask)} pixels in the mask")
    for c in "RGB":
        s_img = sum(image[k][c] for k in keys)
        s_ref = sum(ref[k][c] for k in keys)
        sigma = math.sqrt(sum(ref[k]["variance." + c] for k in keys))
        z = (s_img - s_ref) / sigma if sigma > 0 else float("nan")
        print(f"{c}: image sum {s_img:.6g}  reference sum {s_ref:.6g} +- {sigma:.3g}  "
              f"ratio {s_img / s_ref if s_ref else float('nan'):.4f}  z {z:+.2f}")
    # The standard deviation of the three channels' mean, taking the channels as fully
    # correlated (as in a grey scene): the mean of their standard deviations.
    sd = lambda k: sum(math.sqrt(ref[k]["variance." + c]) for c in "RGB") / 3
    mean = lambda img, k: sum(img[k][c] for c in "RGB") / 3
    zs = []
    for k in keys:
        v, r, s = mean(image, k), mean(ref, k), sd(k)
        zs.append(abs(v - r) / s if s > 0 else (0.0 if v == r else float("inf")))
    zs.sort()
    q = lambda f: zs[min(len(zs) - 1, int(f * len(zs)))]
    print("per-pixel |z| quantiles: 50%% %.2f  90%% %.2f  99%% %.2f  max %.2f" %
          (q(0.5), q(0.9), q(0.99), zs[-1]))
    for k in sorted(keys, key=lambda k: -abs(mean(image, k) - mean(ref, k)))[:5]:
        print("  pixel %s: image %.5g  reference %.5g +- %.3g" %
              (k, mean(image, k), mean(ref, k), sd(k)))

if __name__ == "__main__":
    main()
