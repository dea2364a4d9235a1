#!/usr/bin/env python3
"""ctest RayBench.HitRatesAreConsistent: clpt-raybench on the Cornell box (closed on five
sides, the camera outside its open front). Its closest-hit and any-hit kernels trace the same
incoherent rays with an infinite t_far, so their hit rates must be equal; the pixel-centre
rays mostly enter the box (its front opening fills most of the view: above 0.9); every rate
is a fraction; the JSON names three figures with positive speeds.

    raybench_check.py CLPT_RAYBENCH SCENE
"""
import json
import subprocess
import sys
import tempfile


def main():
    binary, scene = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as tmp:
        out = f"{tmp}/raybench.json"
        subprocess.run([binary, scene, "--device", "pocl", "--res", "32", "--rays", "20000",
                        "--seconds", "0", "--json", out], check=True)
        with open(out) as f:
            doc = json.load(f)
    figures = {f["name"]: f for f in doc["figures"]}
    failures = []
    if sorted(figures) != ["primary closest", "random any", "random closest"]:
        failures.append(f"figures {sorted(figures)}")
    for f in figures.values():
        if not (0.0 <= f["hit_rate"] <= 1.0) or not f["mrays_per_second"] > 0.0:
            failures.append(f"{f['name']}: hit rate {f['hit_rate']}, {f['mrays_per_second']} Mrays/s")
    if figures["random closest"]["hit_rate"] != figures["random any"]["hit_rate"]:
        failures.append("closest and any hit disagree on the same rays: "
                        f"{figures['random closest']['hit_rate']} vs {figures['random any']['hit_rate']}")
    if not figures["primary closest"]["hit_rate"] > 0.9:
        failures.append(f"primary hit rate {figures['primary closest']['hit_rate']} (expected > 0.9)")
    for line in failures:
        print("FAIL:", line)
    print(json.dumps({k: v["hit_rate"] for k, v in figures.items()}))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
