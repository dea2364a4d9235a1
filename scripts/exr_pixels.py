"""Pixel values of an image, read through oiiotool, for the scripts that compare renders
(relmse_masked.py, region_ztest.py). Needs oiiotool."""
import re
import subprocess
import sys


def load_channels(path):
    """{(x, y): {channel name: value}} for every pixel of the image at path."""
    run = lambda *args: subprocess.run(["oiiotool", *args, path], capture_output=True,
                                       text=True, check=True).stdout
    m = re.search(r"channel list:\s*(.*)", run("--info", "-v"))
    if not m:
        sys.exit(f"{path}: no channel list in oiiotool's output")
    names = [n.strip() for n in m.group(1).split(",")]
    pixels = {}
    for line in run("--dumpdata").splitlines():
        m = re.match(r"\s*Pixel \((\d+), (\d+)\): (.*)", line)
        if m:
            values = [float(t) for t in m.group(3).split()]
            pixels[(int(m.group(1)), int(m.group(2)))] = dict(zip(names, values))
    return pixels


def load_rgb(path):
    """{(x, y): [R, G, B]}."""
    return {k: [v["R"], v["G"], v["B"]] for k, v in load_channels(path).items()}
