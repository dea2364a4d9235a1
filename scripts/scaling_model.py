#!/usr/bin/env python3
"""A model of clpt's split renders at many ranks (docs/scaling.md): the time lost to load
imbalance in the per-pass rounds (every rank waits for the slowest share) and the time of the
final reduction (the films added through a binomial tree of the ranks, as gather_to_root does;
the linear gather that preceded it, rank 0 receiving every film in turn, beside it).

Rounds (render/renderer.cpp): each pass gives every device whole samples per pixel in
proportion to its measured speed, at least kMinShareSamples for the slowest; a pass ends when
its slowest share does. Here every rank has the same mean speed and each pass's time on a rank
is the planned time times a log-normal factor of spread `jitter` (OS noise, thermal and clock
variation, network interrupts), independent per rank and pass. Efficiency is the mean busy
time over the pass's length (the maximum over ranks).

The reduction: ceil(log2(K)) rounds, each a film of B bytes through one link (bandwidth W)
and its add (A bytes/s of float adds); the linear gather took K - 1 such steps.

    python3 scripts/scaling_model.py [--jitter 0.02] [--pass-seconds 0.1] [--seed 1]
"""
import argparse
import math
import random


def round_efficiency(ranks, jitter, passes, rng):
    busy = 0.0
    wall = 0.0
    sigma = math.sqrt(math.log(1.0 + jitter * jitter))
    for _ in range(passes):
        times = [rng.lognormvariate(-0.5 * sigma * sigma, sigma) for _ in range(ranks)]
        busy += sum(times) / ranks
        wall += max(times)
    return busy / wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jitter", type=float, default=0.02,
                    help="relative standard deviation of one rank's pass time [0.02]")
    ap.add_argument("--passes", type=int, default=400, help="passes simulated per K [400]")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--bandwidth", type=float, default=10e9,
                    help="bytes/s into rank 0 (100 Gb/s InfiniBand ~ 10e9) [10e9]")
    ap.add_argument("--add-rate", type=float, default=4e9,
                    help="bytes/s of film rank 0 adds (float adds, one core) [4e9]")
    args = ap.parse_args()
    rng = random.Random(args.seed)

    # A 4K film: 3840 x 2160 pixels of sum (16 B), sum of squares (16 B), ray count (4 B), and
    # for splatting integrators (lt, bdpt) the splat film (16 B).
    pixels = 3840 * 2160
    film = {"pt": pixels * 36, "lt/bdpt": pixels * 52}
    print(f"rounds: pass time spread {args.jitter:.1%} per rank, {args.passes} passes")
    print(f"reduction: 4K film, {args.bandwidth / 1e9:g} GB/s into rank 0, adds at "
          f"{args.add_rate / 1e9:g} GB/s")
    print(f"{'K':>5} {'round efficiency':>17} {'tree pt':>8} {'tree lt':>8} {'linear pt':>10} {'linear lt':>10}")
    for k in (1, 2, 4, 8, 16, 32, 64, 128, 256, 512):
        eff = round_efficiency(k, args.jitter, args.passes, rng)
        step = {n: b / args.bandwidth + b / args.add_rate for n, b in film.items()}
        gather = {n: (k - 1) * s for n, s in step.items()}
        tree = {n: (math.ceil(math.log2(k)) * s if k > 1 else 0.0) for n, s in step.items()}
        print(f"{k:>5} {eff:>17.3f} {tree['pt']:>7.2f}s {tree['lt/bdpt']:>7.2f}s "
              f"{gather['pt']:>9.2f}s {gather['lt/bdpt']:>9.2f}s")


if __name__ == "__main__":
    main()
