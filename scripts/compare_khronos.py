#!/usr/bin/env python3
"""Renders each Khronos sample asset of ../shared/scenes (or --scenes) and writes an HTML page
that puts clpt's image next to the asset's own screenshot, for a look by eye.

    scripts/compare_khronos.py [--clpt build/clpt] [--out compare-khronos] [--size 256]
                               [--spp 64] [--integrator pt] [ASSET ...]

Most assets have no lights: the path tracer renders them under a constant white background
(--background 1,1,1) when clpt has that option, else ambient occlusion (--integrator ao, which
shows geometry only). Each render goes to OUT/<asset>.png; OUT/index.html has one row per
asset (render, screenshot, clpt's message when it failed). Exit status 1 when a render fails.
"""
import argparse
import html
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

DEFAULT_ASSETS = [
    "TextureCoordinateTest", "TextureSettingsTest", "TextureTransformTest", "NormalTangentTest",
    "NormalTangentMirrorTest", "AlphaBlendModeTest", "MultiUVTest", "VertexColorTest",
    "WaterBottle", "ToyCar", "MetalRoughSpheresNoTextures", "TransmissionTest",
    "TransmissionRoughnessTest", "EmissiveStrengthTest", "Box",
]


def find_model(folder):
    for variant in ("glTF", "glTF-Binary", "glTF-Embedded"):
        d = os.path.join(folder, variant)
        if os.path.isdir(d):
            for f in sorted(os.listdir(d)):
                if f.endswith((".gltf", ".glb")):
                    return os.path.join(d, f)
    return None


def find_screenshot(folder):
    d = os.path.join(folder, "screenshot")
    if not os.path.isdir(d):
        return None
    names = sorted(os.listdir(d))
    for pref in ("screenshot.png", "screenshot.jpg"):
        if pref in names:
            return os.path.join(d, pref)
    images = [n for n in names if n.lower().endswith((".png", ".jpg", ".jpeg"))]
    return os.path.join(d, images[0]) if images else None


def has_background(clpt):
    out = subprocess.run([clpt, "--help"], capture_output=True, text=True).stdout
    return "--background" in out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("assets", nargs="*", help="asset folder names [a list of texture/material tests]")
    ap.add_argument("--scenes", default=os.path.join(ROOT, "..", "shared", "scenes"))
    ap.add_argument("--clpt", default=os.path.join(ROOT, "build", "clpt"))
    ap.add_argument("--out", default="compare-khronos")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--integrator", default="pt")
    ap.add_argument("--extra", default="", help="more clpt arguments, space separated")
    args = ap.parse_args()

    os.makedirs(args.out, exist_ok=True)
    background = args.integrator != "ao" and has_background(args.clpt)
    integrator = args.integrator if background or args.integrator == "ao" else "ao"
    rows, failed = [], 0
    for name in args.assets or DEFAULT_ASSETS:
        folder = os.path.join(args.scenes, name)
        model = find_model(folder)
        if model is None:
            rows.append((name, None, None, "no .gltf/.glb found"))
            continue
        out = os.path.abspath(os.path.join(args.out, name + ".png"))
        cmd = [args.clpt, model, "-o", out, "--spp", str(args.spp), "--resolution",
               "%dx%d" % (args.size, args.size), "--integrator", integrator, "-q"]
        if background:
            cmd += ["--background", "1,1,1"]
        cmd += args.extra.split()
        r = subprocess.run(cmd, capture_output=True, text=True)
        msg = (r.stderr.strip() or "") if r.returncode == 0 else "exit %d: %s" % (r.returncode, r.stderr.strip())
        if r.returncode != 0:
            failed += 1
        shot = find_screenshot(folder)
        rows.append((name, out if r.returncode == 0 else None, os.path.abspath(shot) if shot else None, msg))
        print("%-28s %s" % (name, "ok" if r.returncode == 0 else msg.splitlines()[0] if msg else "failed"))

    with open(os.path.join(args.out, "index.html"), "w") as f:
        f.write("<!doctype html><meta charset=utf-8><title>clpt vs Khronos screenshots</title>\n")
        f.write("<style>img{width:%dpx;image-rendering:pixelated}td{vertical-align:top;padding:4px}</style>\n" % args.size)
        f.write("<p>clpt %s, %d spp, %dx%d%s</p><table>\n" % (integrator, args.spp, args.size, args.size,
                                                               ", white background" if background else ""))
        f.write("<tr><th>asset</th><th>clpt</th><th>screenshot</th><th>messages</th></tr>\n")
        for name, img, shot, msg in rows:
            f.write("<tr><td>%s</td><td>%s</td><td>%s</td><td><pre>%s</pre></td></tr>\n" % (
                html.escape(name),
                '<img src="file://%s">' % html.escape(img) if img else "",
                '<img src="file://%s">' % html.escape(shot) if shot else "",
                html.escape(msg)))
        f.write("</table>\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
