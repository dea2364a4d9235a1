#!/usr/bin/env python3
"""Checks that the kernels' includes go one way down the layers of docs/ARCHITECTURE.md
("Kernel layers"), and that no integrator includes another integrator's files.

    scripts/kernel_layers.py [--kernels DIR]     exit 1 naming every include that breaks a rule
    scripts/kernel_layers.py --self-test         plants each kind of violation in a copy of
                                                 the kernels; exit 1 unless each is reported

Layers, lowest first (a file may include its own layer and the ones below):
  core (core/, shared/, sampler/), geometry, textures and materials (texture/, material/),
  BVH, BSDF, lights, camera and film, spatial, integrator stages (integrators/stages/),
  shared estimators (integrators/estimators/), integrators (integrators/<family>/),
  entry points (integrators/*.cl; tools/*.cl, the tools' kernels).
Headers (*.h) hold types and trivial helpers: they count as core and may include only core.
Rules beyond the order: an integrator family's files include no other family's; an entry
point includes no other entry point.
"""
import argparse
import os
import re
import shutil
import sys
import tempfile

LOWER = [("core", "shared", "sampler"), ("geometry",), ("texture", "material"), ("bvh",),
         ("bsdf",), ("light",), ("camera", "film"), ("spatial",)]
STAGES, ESTIMATORS, FAMILY, ENTRY = 8, 9, 10, 11
NAMES = ["core", "geometry", "textures and materials", "BVH", "BSDF", "lights",
         "camera and film", "spatial", "integrator stages", "shared estimators", "integrators",
         "entry points"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer(path):
    """(layer index, integrator family or None) of a path relative to kernels/; None if the
    path is not a kernel file (a system or test header)."""
    parts = path.split("/")
    if path.endswith(".h"):
        return 0, None
    if parts[0] == "tools":
        return ENTRY, None  # the tools' entry points (clpt-raybench)
    if parts[0] != "integrators":
        for i, folders in enumerate(LOWER):
            if parts[0] in folders:
                return i, None
        return None, None
    if len(parts) == 2:
        return ENTRY, None
    if parts[1] == "stages":
        return STAGES, None
    if parts[1] == "estimators":
        return ESTIMATORS, None
    return FAMILY, parts[1]


def violations(kernels):
    found = []
    for folder, _, files in os.walk(kernels):
        for name in sorted(files):
            if not name.endswith((".cl", ".h")):
                continue
            rel = os.path.relpath(os.path.join(folder, name), kernels).replace(os.sep, "/")
            own, family = layer(rel)
            if own is None:
                found.append(f"{rel}: in no layer (add its folder to scripts/kernel_layers.py "
                             "and docs/ARCHITECTURE.md)")
                continue
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                text = f.read()
            for m in INCLUDE.finditer(text):
                inc = m.group(1)
                if not os.path.exists(os.path.join(kernels, inc)):
                    continue  # not a kernel file
                theirs, their_family = layer(inc)
                line = text.count("\n", 0, m.start()) + 1
                where = f"{rel}:{line}: includes {inc}"
                if theirs > own:
                    found.append(f"{where}: {NAMES[theirs]} above {NAMES[own]}")
                elif own == FAMILY and theirs == FAMILY and their_family != family:
                    found.append(f"{where}: integrator {family} includes integrator "
                                 f"{their_family}'s file (shared code belongs in "
                                 "integrators/estimators/ or integrators/stages/)")
                elif own == ENTRY and theirs == ENTRY:
                    found.append(f"{where}: an entry point includes another")
    return found


def self_test(kernels):
    """Each planted include must be reported, and the unplanted copy must be clean."""
    plants = [
        ("geometry/surface.cl", "integrators/stages/walk.cl", "above"),
        ("integrators/stages/walk.cl", "integrators/estimators/path_trace.cl", "above"),
        ("integrators/estimators/path_trace.cl", "integrators/pt.cl", "above"),
        ("integrators/vcm/vcm_path.cl", "integrators/mlt/chain.cl", "integrator vcm includes"),
        ("integrators/bdpt.cl", "integrators/pt.cl", "entry point includes another"),
        ("bsdf/bsdf_params.h", "bsdf/bsdf.cl", "above"),
    ]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        clean = violations(kernels)
        if clean:
            print("self-test: the kernels themselves break the layers:\n  " + "\n  ".join(clean))
            return 1
        for target, include, expect in plants:
            copy = os.path.join(tmp, "kernels")
            shutil.rmtree(copy, ignore_errors=True)
            shutil.copytree(kernels, copy)
            with open(os.path.join(copy, target), "a", encoding="utf-8") as f:
                f.write(f'\n#include "{include}"\n')
            found = violations(copy)
            caught = any(target in v and include in v and expect in v for v in found)
            print(f"self-test: {target} including {include}: "
                  f"{'reported' if caught else 'NOT reported'}")
            failures += not caught
    return 1 if failures else 0


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kernels", default=os.path.join(here, "..", "kernels"))
    ap.add_argument("--self-test", action="store_true")
    args = ap.parse_args()
    if args.self_test:
        return self_test(args.kernels)
    found = violations(args.kernels)
    for v in found:
        print(v)
    print(f"kernel layers: {len(found)} violation(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
