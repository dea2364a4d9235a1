#!/usr/bin/env python3
"""Render a scene with every estimator strategy x sampler for equal time and write an HTML
report comparing them against a high-spp reference.

    scripts/efficiency_report.py [--scene scenes/cornell_box.gltf] [--time 4]
        [--resolution 128x128] [--reference-spp 4096 | --reference FILE.exr] [--out report/]
        [--clpt build/clpt] [--clpt-diff build/clpt-diff] [--backend auto|module|process] [--quick]

Steps:
  1. Reference: two independent halves of --reference-spp samples (different seeds),
     averaged with oiiotool; their difference estimates the reference's own error.
     --reference FILE reuses an EXR instead.
  2. Every configuration (strategy x sampler) renders for --time seconds with --stats;
     stratified and lhs need --spp, so they get the spp that the independent sampler with
     the same strategy reached in the time budget. clpt-diff compares each with the
     reference and writes an error map; oiiotool converts the EXR to an sRGB PNG.
  3. A few configurations also render at T/8, T/4 and T/2 for a convergence plot.
  4. index.html (plain HTML, inline CSS and SVG) and results.json go into --out, with the
     images beside them in subfolders, and commands.txt lists every command run.

Efficiency is 1 / (relMSE x seconds) with clpt's render seconds from --stats. Each render's
CPU time (user + system, from rusage, less a measured start-up) is recorded too: other jobs
on a shared machine change wall-clock seconds a lot and CPU seconds little, so the report
also gives 1 / (relMSE x CPU seconds) and warns when the share of CPU clpt got varied.

The report is built in a temporary folder beside --out and renamed into place only when
complete and checked (a row per configuration, no NaN relMSE, every image present), so a
failed or interrupted run never leaves a half-written report. Exit status: 0 written,
1 failure (message on stderr: a tool missing, a render or comparison failed, the check
failed), 2 bad command line, 130 interrupted (SIGINT or SIGTERM).

Python 3 standard library; renders go through the clpt Python module in-process where it
imports (with NumPy; docs/python.md), else through a clpt process each (--backend).
"""

from __future__ import annotations

import argparse
import datetime
import html
import json
import math
import os
import re
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
MARKER = ".clpt-efficiency-report"  # marks a folder this script wrote, so it may replace it

# (id, label, clpt options). The first is the baseline that others are compared with.
STRATEGIES = [
    ("mis", "MIS, power heuristic (default)", ["--direct", "mis"]),
    ("light", "light sampling only (NEE)", ["--direct", "light"]),
    ("bsdf", "BSDF sampling only (no NEE)", ["--direct", "bsdf"]),
    ("balance", "MIS, balance heuristic", ["--mis", "balance"]),
    ("cosine", "cosine hemisphere", ["--hemisphere", "cosine"]),
    ("uniform", "uniform hemisphere", ["--hemisphere", "uniform"]),
    ("ls4", "4 light samples per vertex", ["--light-samples", "4"]),
    ("branch4", "branching 4 at the first hit", ["--branching", "4"]),
    ("rrfixed", "Russian roulette fixed:0.5", ["--rr", "fixed:0.5"]),
]
SAMPLERS = ["independent", "stratified", "lhs", "sobol"]
NEEDS_SPP = ("stratified", "lhs")  # these samplers divide among a known sample count
BASELINE = "mis-independent"
DEFAULT_CONVERGENCE = ["mis-independent", "mis-sobol", "mis-stratified", "bsdf-independent"]

QUICK = dict(resolution="32x32", time=0.3, reference_spp=2048,
             configs=["mis-independent", "mis-stratified", "mis-lhs", "mis-sobol",
                      "bsdf-independent"],
             convergence=["mis-independent", "mis-sobol"], fractions=[0.25, 0.5])
FRACTIONS = [0.125, 0.25, 0.5]  # of --time, besides the full-time run, for the plot

# Okabe-Ito colours (distinguishable with colour-blindness) and dash patterns.
COLOURS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"]
DASHES = ["", "6,3", "2,3", "8,3,2,3", "1,2", "4,2,1,2", "10,4"]


class ReportError(Exception):
    """A failure with a message for the user; the script exits 1."""


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


# ---- running tools ----------------------------------------------------------------------


@dataclass
class Runner:
    clpt: str
    clpt_diff: str
    oiiotool: str | None
    device: str | None
    workdir: Path
    commands: list[str] = field(default_factory=list)
    last_cpu: float = 0.0
    module: object = None  # the clpt Python module, when renders run in-process (--backend module)

    def render_in_process(self, scene: str, args: list[str], what: str, cmd: list[str]) -> None:
        """The render of `cmd` through the Python module (docs/python.md): the same options,
        files and statistics, without a process per render. CPU seconds are this process's
        (PoCL's threads included) over the call."""
        self.commands.append(shlex.join(cmd) + "  # in-process: clpt.render")
        kwargs: dict = {}
        i = 0
        while i < len(args):  # "--name=value", "--name value" and "--flag" to keywords
            name, eq, value = args[i][2:].partition("=")
            key = name.replace("-", "_")
            if eq:
                kwargs[key] = value
            elif i + 1 < len(args) and not args[i + 1].startswith("--"):
                i += 1
                kwargs[key] = args[i]
            else:
                kwargs[key] = True
            i += 1
        if self.device:
            kwargs["device"] = self.device
        before = resource.getrusage(resource.RUSAGE_SELF)
        cwd = os.getcwd()
        os.chdir(self.workdir)
        try:
            self.module.render(scene, quiet=True, **kwargs)
        except self.module.Error as e:
            raise ReportError(f"render {what} failed (exit {e.exit_code}):\n  {shlex.join(cmd)}\n{e}")
        finally:
            os.chdir(cwd)
        after = resource.getrusage(resource.RUSAGE_SELF)
        self.last_cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)

    def run(self, cmd: list[str], what: str, timeout: float | None = None) -> str:
        """Runs cmd in the work folder; returns stdout, raises ReportError on failure."""
        self.commands.append(shlex.join(cmd))
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        try:
            p = subprocess.run(cmd, cwd=self.workdir, capture_output=True, text=True,
                               timeout=timeout)
        except FileNotFoundError:
            raise ReportError(f"{what}: cannot run {cmd[0]}")
        except subprocess.TimeoutExpired:
            raise ReportError(f"{what}: timed out after {timeout:.0f} s:\n  {shlex.join(cmd)}")
        if p.returncode != 0:
            tail = "\n".join((p.stderr or p.stdout).strip().splitlines()[-15:])
            raise ReportError(f"{what} failed (exit {p.returncode}):\n  {shlex.join(cmd)}\n{tail}")
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        # CPU seconds of this child (runs are sequential): the work it did, whatever else
        # the machine was running, unlike wall-clock time.
        self.last_cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return p.stdout

    def clpt_cmd(self, scene: str, args: list[str]) -> list[str]:
        cmd = [self.clpt]
        if self.device:
            cmd.append(f"--device={self.device}")
        return cmd + ["--quiet", scene] + args

    def render(self, scene: str, args: list[str], exr: str, stats: str, what: str,
               timeout: float | None) -> dict:
        # --variance puts each pixel's variance into the EXR, so clpt-diff can z-test it.
        cmd = self.clpt_cmd(scene, args + ["--variance", f"--stats={stats}", "-o", exr])
        if self.module is not None:
            self.render_in_process(scene, args + ["--variance", f"--stats={stats}", f"--output={exr}"],
                                   what, cmd)
        else:
            self.run(cmd, f"render {what}", timeout)
        if not (self.workdir / exr).is_file():
            raise ReportError(f"render {what}: clpt wrote no image (no sample taken?):\n  "
                              f"{shlex.join(cmd)}")
        st = json.loads((self.workdir / stats).read_text())
        if st.get("interrupted"):
            raise ReportError(f"render {what} was interrupted")
        if int(st.get("spp", 0)) < 1:
            raise ReportError(f"render {what}: 0 samples per pixel in the time budget")
        st["process_cpu_seconds"] = self.last_cpu
        return st

    def diff(self, exr: str, ref: str, err_png: str | None, what: str) -> dict:
        cmd = [self.clpt_diff, "--json"]
        if err_png:
            cmd += ["--error-map", err_png, "--error-range", "1e-6", "1"]
        out = self.run(cmd + [exr, ref], f"clpt-diff of {what}", timeout=120)
        try:
            return json.loads(out)
        except json.JSONDecodeError as e:
            raise ReportError(f"clpt-diff of {what}: output is not JSON ({e})")

    def to_png(self, exr: str, png: str, what: str, scene: str, args: list[str] | None) -> None:
        """sRGB PNG of exr: oiiotool, or else clpt renders the same image again as a PNG
        (same options, seed and spp give a bit-identical image, however the passes fall)."""
        if self.oiiotool:
            self.run([self.oiiotool, exr, "--colorconvert", "linear", "sRGB", "-d", "uint8",
                      "-o", png], f"PNG conversion of {what}", timeout=120)
        else:
            self.run(self.clpt_cmd(scene, args + ["-o", png]), f"PNG render of {what}")


def load_module(backend: str):
    """The clpt Python module (build/python, or wherever PYTHONPATH finds it), or None for the
    process backend. 'module' requires it; 'auto' takes it when it and NumPy import."""
    if backend == "process":
        return None
    build_python = REPO / "build" / "python"
    if build_python.is_dir() and str(build_python) not in sys.path:
        sys.path.append(str(build_python))
    try:
        import numpy  # noqa: F401  (the module's arrays)
        import clpt as module
        return module
    except ImportError as e:
        if backend == "module":
            raise ReportError(f"--backend module: cannot import the clpt module ({e}); build it "
                              "(CMake option CLPT_PYTHON) or set PYTHONPATH")
        return None


def oiiotool_usable(oiiotool: str) -> bool:
    """oiiotool exists and knows --colorconvert to sRGB."""
    try:
        p = subprocess.run([oiiotool, "--help"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return False
    text = p.stdout + p.stderr
    return "--colorconvert" in text and "sRGB" in text


def find_tool(given: str, default: Path, name: str, hint: str) -> str:
    path = given if given else str(default)
    if os.sep not in path:
        found = shutil.which(path)
        if found:
            return found
    p = Path(path).resolve()
    if not (p.is_file() and os.access(p, os.X_OK)):
        raise ReportError(f"{name} not found at {path} ({hint})")
    return str(p)


def tool_version(cmd: list[str]) -> str:
    try:
        p = subprocess.run(cmd + ["--version"], capture_output=True, text=True, timeout=30)
        return (p.stdout or p.stderr).strip().splitlines()[0] if p.returncode == 0 else "?"
    except (OSError, subprocess.TimeoutExpired, IndexError):
        return "?"


# ---- numbers ------------------------------------------------------------------------------


def num(x) -> float:
    """JSON number or null (clpt-diff writes NaN as null) to float."""
    return float("nan") if x is None else float(x)


def fmt(x: float, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "NaN"
    if math.isinf(x):
        return "∞"
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        decimals = max(0, digits - 1 - int(math.floor(math.log10(a))))
        return f"{x:.{decimals}f}"
    m, e = f"{x:.{digits - 1}e}".split("e")
    return f"{m}×10<sup>{int(e)}</sup>".replace("<sup>-", "<sup>−")


def plain(x: float, digits: int = 3) -> str:
    return re.sub(r"×10<sup>([−-]?\d+)</sup>", r"e\1", fmt(x, digits)).replace("−", "-")


def grid_width(n: int) -> int:
    """The stratified sampler's grid width: the largest divisor of n not above sqrt(n)."""
    r = math.isqrt(n)
    while n % r:
        r -= 1
    return r


def stratified_spp(n: int) -> int:
    """A sample count at most n and at least 97 % of it whose nx x ny grid is as square as
    possible (a prime n would give 1 x n strips), preferring the larger count."""
    best = n
    best_score = grid_width(n) / (n // grid_width(n))
    for m in range(n - 1, max(1, math.ceil(0.97 * n)) - 1, -1):
        score = grid_width(m) / (m // grid_width(m))
        if score > best_score + 1e-12:
            best, best_score = m, score
    return best


def loglog_slope(points: list[tuple[float, float]]) -> float:
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


# ---- configurations -------------------------------------------------------------------------


@dataclass
class Config:
    strategy: str
    sampler: str
    label: str
    args: list[str]

    @property
    def id(self) -> str:
        return f"{self.strategy}-{self.sampler}"

    def options(self) -> list[str]:
        return self.args + ["--sampler", self.sampler]


def make_configs(ids: list[str]) -> list[Config]:
    strategies = {s[0]: s for s in STRATEGIES}
    out = []
    for cid in ids:
        strat, _, sampler = cid.partition("-")
        if strat not in strategies or sampler not in SAMPLERS:
            raise ReportError(f"unknown configuration {cid!r}: use STRATEGY-SAMPLER with "
                              f"STRATEGY in {', '.join(strategies)} and SAMPLER in "
                              f"{', '.join(SAMPLERS)}")
        out.append(Config(strat, sampler, strategies[strat][1], list(strategies[strat][2])))
    # Independent runs first: stratified and lhs take their spp from them.
    order = {s: i for i, s in enumerate(["independent", "sobol", "stratified", "lhs"])}
    strat_order = {s[0]: i for i, s in enumerate(STRATEGIES)}
    out.sort(key=lambda c: (strat_order[c.strategy], order[c.sampler]))
    have = {c.id for c in out}
    for c in out:
        if c.sampler in NEEDS_SPP and f"{c.strategy}-independent" not in have:
            raise ReportError(f"{c.id} needs {c.strategy}-independent too: the {c.sampler} "
                              f"sampler gets the spp that the independent sampler reached")
    return out


# ---- SVG plot -----------------------------------------------------------------------------

SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def tick_label(v: float, sci: bool) -> str:
    e = math.floor(math.log10(v) + 1e-9)
    m = round(v / 10 ** e)
    if not sci and -2 <= e <= 3:
        return f"{v:g}"
    if -1 <= e <= 1:  # 0.1, 1, 10 read better than powers
        return f"{v:g}"
    p = ("10" + str(e).translate(SUPERSCRIPT))
    return p if m == 1 else f"{m}×{p}"


def log_ticks(lo: float, hi: float) -> tuple[list[float], list[float]]:
    """Labelled and unlabelled tick values in [lo, hi] for a log axis."""
    major, minor = [], []
    span = math.log10(hi / lo)
    for e in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1):
        for m in range(1, 10):
            v = m * 10.0 ** e
            if lo * (1 - 1e-9) <= v <= hi * (1 + 1e-9):
                labelled = m == 1 or (span < 2.5 and m in (2, 5)) or (span < 1.2 and m in (3, 4))
                (major if labelled else minor).append(v)
    return major, minor


def svg_loglog(series: list[dict], xlabel: str, ylabel: str, floor: float | None,
               slope_anchor: tuple[float, float] | None, uid: str = "plot",
               slope_label: str = "slope −1: relMSE ∝ 1/time") -> str:
    """A log-log line plot as inline SVG. series: [{label, colour, dash, points}]."""
    W, H = 680, 430
    left, right, top, bottom = 78, 20, 16, 52
    pw, ph = W - left - right, H - top - bottom
    xs = [x for s in series for x, _ in s["points"]]
    ys = [y for s in series for _, y in s["points"] if y > 0]
    if floor and floor > 0:
        ys.append(floor)
    if not xs or not ys:
        return "<p>(no data to plot)</p>"
    x0, x1 = min(xs) / 1.3, max(xs) * 1.3
    y0, y1 = min(ys) / 1.6, max(ys) * 1.6

    def px(x: float) -> float:
        return left + pw * math.log(x / x0) / math.log(x1 / x0)

    def py(y: float) -> float:
        return top + ph * (1 - math.log(y / y0) / math.log(y1 / y0))

    e = html.escape
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
         f'viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12" role="img" '
         f'aria-label="{e(ylabel)} against {e(xlabel)}, log-log">',
         f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="white" stroke="#444"/>']
    for axis in ("x", "y"):
        lo, hi = (x0, x1) if axis == "x" else (y0, y1)
        major, minor = log_ticks(lo, hi)
        for v, lab in [(v, True) for v in major] + [(v, False) for v in minor]:
            if axis == "x":
                p = px(v)
                o.append(f'<line x1="{p:.1f}" y1="{top}" x2="{p:.1f}" y2="{top + ph}" '
                         f'stroke="{"#ddd" if lab else "#f0f0f0"}"/>')
                o.append(f'<line x1="{p:.1f}" y1="{top + ph}" x2="{p:.1f}" '
                         f'y2="{top + ph + (6 if lab else 3)}" stroke="#444"/>')
                if lab:
                    o.append(f'<text x="{p:.1f}" y="{top + ph + 19}" text-anchor="middle">'
                             f'{e(tick_label(v, False))}</text>')
            else:
                p = py(v)
                o.append(f'<line x1="{left}" y1="{p:.1f}" x2="{left + pw}" y2="{p:.1f}" '
                         f'stroke="{"#ddd" if lab else "#f0f0f0"}"/>')
                o.append(f'<line x1="{left - (6 if lab else 3)}" y1="{p:.1f}" x2="{left}" '
                         f'y2="{p:.1f}" stroke="#444"/>')
                if lab:
                    o.append(f'<text x="{left - 9}" y="{p + 4:.1f}" text-anchor="end">'
                             f'{e(tick_label(v, True))}</text>')
    o.append(f'<text x="{left + pw / 2:.0f}" y="{H - 10}" text-anchor="middle">{e(xlabel)}</text>')
    o.append(f'<text transform="translate(16 {top + ph / 2:.0f}) rotate(-90)" '
             f'text-anchor="middle">{e(ylabel)}</text>')
    o.append(f'<clipPath id="{uid}-area"><rect x="{left}" y="{top}" width="{pw}" '
             f'height="{ph}"/></clipPath><g clip-path="url(#{uid}-area)">')
    legend = []
    if slope_anchor:
        ax, ay = slope_anchor
        o.append(f'<line x1="{px(x0):.1f}" y1="{py(ay * ax / x0):.1f}" x2="{px(x1):.1f}" '
                 f'y2="{py(ay * ax / x1):.1f}" stroke="#888" stroke-width="1.5" '
                 f'stroke-dasharray="3,4"/>')
        legend.append((slope_label, "#888", "3,4", False))
    if floor and floor > 0:
        o.append(f'<line x1="{left}" y1="{py(floor):.1f}" x2="{left + pw}" y2="{py(floor):.1f}" '
                 f'stroke="#b00" stroke-width="1" stroke-dasharray="1,3"/>')
        legend.append(("reference's own error (estimate)", "#b00", "1,3", False))
    for s in series:
        pts = sorted(s["points"])
        path = " ".join(f"{'M' if i == 0 else 'L'}{px(x):.1f},{py(y):.1f}"
                        for i, (x, y) in enumerate(pts) if y > 0)
        dash = f' stroke-dasharray="{s["dash"]}"' if s["dash"] else ""
        o.append(f'<path d="{path}" fill="none" stroke="{s["colour"]}" stroke-width="2"{dash}/>')
        for x, y in pts:
            if y > 0:
                o.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3.5" '
                         f'fill="{s["colour"]}"><title>{e(s["label"])}: {x:.3g} s, '
                         f'relMSE {y:.3g}</title></circle>')
        legend.insert(len(legend), (s["label"], s["colour"], s["dash"], True))
    o.append("</g>")
    # Legend, bottom left inside the plot: the curves fall from top left to bottom right.
    lw = 12 + 7 * max(len(t[0]) for t in legend) + 40
    lh = 8 + 18 * len(legend)
    lx, ly = left + 8, top + ph - lh - 8
    o.append(f'<rect x="{lx}" y="{ly}" width="{lw}" height="{lh}" fill="white" '
             f'fill-opacity="0.9" stroke="#aaa"/>')
    for i, (label, colour, dash, marker) in enumerate(legend):
        yy = ly + 14 + 18 * i
        d = f' stroke-dasharray="{dash}"' if dash else ""
        o.append(f'<line x1="{lx + 8}" y1="{yy - 4}" x2="{lx + 38}" y2="{yy - 4}" '
                 f'stroke="{colour}" stroke-width="2"{d}/>')
        if marker:
            o.append(f'<circle cx="{lx + 23}" cy="{yy - 4}" r="3.5" fill="{colour}"/>')
        o.append(f'<text x="{lx + 46}" y="{yy}">{e(label)}</text>')
    o.append("</svg>")
    return "\n".join(o)


# ---- the report ---------------------------------------------------------------------------

CSS = """
body { font-family: sans-serif; max-width: 1100px; margin: 1.5em auto; padding: 0 1em;
       color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8em 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; vertical-align: top; }
th { background: #f3f3f3; } td.l, th.l { text-align: left; }
tr.baseline td { background: #fff8dc; }
td.best { font-weight: bold; }
code { background: #f5f5f5; padding: 0 3px; }
img.px { image-rendering: pixelated; image-rendering: crisp-edges; display: block; }
.grid td { text-align: center; font-size: 0.85em; }
.pair { display: flex; gap: 3px; justify-content: center; }
.meta td { text-align: left; }
.note { color: #555; font-size: 0.92em; }
.warn { background: #fff3e0; border-left: 4px solid #e69f00; padding: 0.4em 0.8em; }
pre { background: #f7f7f7; padding: 0.6em; overflow-x: auto; font-size: 0.82em; }
"""


def write_html(path: Path, ctx: dict) -> None:
    e = html.escape
    res = ctx["results"]
    base = next((r for r in res if r["id"] == BASELINE), None)
    base_eff = base["eff_relmse"] if base else float("nan")
    ranked = sorted(res, key=lambda r: -r["eff_relmse"] if not math.isnan(r["eff_relmse"])
                    else math.inf)
    ref = ctx["reference"]
    w, h = ctx["width"], ctx["height"]
    thumb = max(w, min(128, 4 * w)) if w < 128 else w  # small renders are shown enlarged
    thumb_h = round(thumb * h / w)
    has_z = any(r.get("z_pass") is not None for r in res)
    any_strat = any(r["sampler"] in NEEDS_SPP for r in res)
    o = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
         f"<title>clpt efficiency report: {e(ctx['scene_name'])}</title>",
         f"<style>{CSS}</style></head><body>",
         f"<h1>clpt efficiency report: {e(ctx['scene_name'])}</h1>"]

    # Summary.
    o.append("<p>Each configuration (estimator strategy × sampler) rendered the scene for the "
             f"same time budget, {ctx['time']:g} s, at {w}×{h}. Its error is measured against "
             "a high-spp reference; the ranking is by <b>efficiency = 1 / (relMSE × seconds)</b>, "
             "which does not depend on how long each ran as long as relMSE falls as 1/time. "
             "Higher is better.</p>")
    if ranked and base:
        top, worst = ranked[0], ranked[-1]
        by_cpu = sorted(res, key=lambda r: -r["eff_cpu"] if math.isfinite(r["eff_cpu"])
                        else math.inf)
        o.append("<ul>")
        o.append(f"<li>Best: <b>{e(top['id'])}</b> ({e(top['label'])}, {e(top['sampler'])} "
                 f"sampler), {fmt(top['eff_relmse'] / base_eff)}× the efficiency of the "
                 f"default <code>{BASELINE}</code>; then "
                 + ", ".join(f"{e(r['id'])} {fmt(r['eff_relmse'] / base_eff)}×"
                             for r in ranked[1:3]) + ".</li>")
        o.append(f"<li>Worst: <b>{e(worst['id'])}</b>, "
                 f"{fmt(worst['eff_relmse'] / base_eff)}× the default.</li>")
        o.append("<li>Per CPU second (steadier when the machine is shared, see below): "
                 + ", ".join(f"{e(r['id'])} {fmt(r['eff_cpu'] / base['eff_cpu'])}×"
                             for r in by_cpu[:3]) + ".</li>")
        o.append(f"<li>The default ({BASELINE}) reached {base['spp']} spp in "
                 f"{base['seconds']:.2f} s, relMSE {fmt(base['relmse'])}.</li>")
        o.append("</ul>")
    shares = [r["cpu_seconds"] / r["seconds"] for r in res if r["seconds"] > 0]
    if shares and max(shares) > 1.25 * min(shares):
        o.append(f"<p class='warn'><b>The machine was shared.</b> clpt got between "
                 f"{min(shares):.2f} and {max(shares):.2f} CPUs' worth of time during its "
                 "renders (CPU seconds / seconds), so equal wall-clock time did not mean equal "
                 "work: differences of up to that factor in the wall-clock efficiency (and "
                 "the ranking by it) can be other jobs' doing. The efficiency per CPU second "
                 "(last columns) is the steadier comparison here; for a clean wall-clock one, "
                 "run the report on an idle machine.</p>")

    o.append('<table class="meta">')
    meta_rows = [
        ("scene", f"<code>{e(ctx['scene'])}</code>"),
        ("resolution", f"{w}×{h}"),
        ("time per configuration", f"{ctx['time']:g} s (render time; start-up excluded)"),
        ("reference", ref["description"]),
        ("reference's own error", ref["floor_text"]),
        ("device", e(ctx["device"])),
        ("programs", e(ctx["versions"])),
        ("machine", e(ctx["machine"])),
        ("written", e(ctx["date"]) + f", whole report took {ctx['wall']:.0f} s"),
    ]
    for k, v in meta_rows:
        o.append(f'<tr><th class="l">{e(k)}</th><td>{v}</td></tr>')
    o.append("</table>")

    # Ranking.
    o.append("<h2>Ranking</h2>")
    o.append("<table><tr><th>rank</th><th class='l'>configuration</th><th class='l'>clpt options</th>"
             "<th>spp</th><th>seconds</th><th>M paths/s</th><th>mean variance<br>(--stats)</th>"
             "<th>efficiency<br>1/(variance·s)</th><th>relMSE</th><th>efficiency<br>"
             "1/(relMSE·s)</th><th>vs default</th><th>CPU s</th><th>1/(relMSE·CPU s)<br>"
             "vs default</th>"
             + ("<th>z-test pass</th>" if has_z else "") + "</tr>")
    base_cpu = base["eff_cpu"] if base else float("nan")
    for i, r in enumerate(ranked, 1):
        spp = f"{r['spp']}"
        if r["sampler"] in NEEDS_SPP:
            spp += f"<sup>*</sup>"
        cls = "config baseline" if r["id"] == BASELINE else "config"
        o.append(f'<tr class="{cls}" data-id="{e(r["id"])}" data-relmse="{r["relmse"]!r}">'
                 f"<td>{i}</td><td class='l'><a href='#img-{e(r['id'])}'>{e(r['id'])}</a><br>"
                 f"<span class='note'>{e(r['label'])}</span></td>"
                 f"<td class='l'><code>{e(' '.join(r['options']))}</code></td>"
                 f"<td>{spp}</td><td>{r['seconds']:.2f}</td>"
                 f"<td>{fmt(r['paths_per_second'] / 1e6)}</td><td>{fmt(r['mean_variance'])}</td>"
                 f"<td>{fmt(r['eff_variance'])}</td><td>{fmt(r['relmse'])}</td>"
                 f"<td><b>{fmt(r['eff_relmse'])}</b></td>"
                 f"<td>{fmt(r['eff_relmse'] / base_eff) + '×' if base else '–'}</td>"
                 f"<td>{r['cpu_seconds']:.2f}</td>"
                 f"<td>{fmt(r['eff_cpu'] / base_cpu) + '×' if base else '–'}</td>"
                 + (f"<td>{fmt(100 * r['z_pass']) + ' %' if r.get('z_pass') is not None else '–'}</td>"
                    if has_z else "") + "</tr>")
    o.append("</table>")
    if any_strat:
        ratios = sorted(r["seconds"] / ctx["time"] for r in res if r["sampler"] in NEEDS_SPP)
        o.append("<p class='note'><sup>*</sup> stratified and lhs divide the pixel's samples "
                 "into strata, so they need the sample count in advance (<code>--spp</code>) "
                 "instead of <code>--time</code>. Each got the spp that the independent sampler "
                 "with the same strategy reached in the time budget (stratified: rounded down by "
                 "at most 3 % to a count with a squarer grid), so that it runs for about the "
                 f"same time. Here they took {ratios[0]:.2f}–{ratios[-1]:.2f}× the budget "
                 f"(median {ratios[len(ratios) // 2]:.2f}×): a sample of these samplers costs "
                 "more than an independent one (and the machine's load varies), so their "
                 "images had that much more time. Efficiency uses the seconds each render "
                 "actually took, so the ranking stays fair.</p>")
    o.append("<p class='note'><b>CPU s</b> is the CPU time clpt used (user + system, all "
             "threads) less a run's start-up. Unlike wall-clock seconds it hardly depends on "
             "what else the machine runs, so when the load average above is high, the last "
             "column (efficiency per CPU second, relative to the default) is the steadier "
             "ranking; <b>M paths/s</b> shows how much each render was slowed.</p>")

    # Matrix.
    strategies = [s for s in STRATEGIES if any(r["strategy"] == s[0] for r in res)]
    samplers = [s for s in SAMPLERS if any(r["sampler"] == s for r in res)]
    if base and len(res) > 1:
        o.append("<h2>Efficiency relative to the default</h2>")
        o.append(f"<p>1/(relMSE·s) divided by that of <code>{BASELINE}</code>; above 1 is "
                 "better than the default. In brackets the same per CPU second, "
                 "1/(relMSE·CPU s). Bold: the best sampler for each strategy (by the first "
                 "figure).</p>")
        o.append("<table><tr><th class='l'>strategy</th>"
                 + "".join(f"<th>{e(s)}</th>" for s in samplers) + "</tr>")
        by_id = {r["id"]: r for r in res}
        for sid, label, _ in strategies:
            row = [by_id.get(f"{sid}-{s}") for s in samplers]
            vals = [r["eff_relmse"] / base_eff if r else None for r in row]
            best = max((v for v in vals if v is not None and not math.isnan(v)), default=None)
            cells = "".join(
                "<td>–</td>" if r is None else
                f"<td{' class=best' if v == best else ''}>{fmt(v)}× "
                f"<span class='note'>({fmt(r['eff_cpu'] / base['eff_cpu'])}×)</span></td>"
                for r, v in zip(row, vals))
            o.append(f"<tr><td class='l'>{e(sid)}: {e(label)}</td>{cells}</tr>")
        o.append("</table>")

    # Convergence.
    conv = ctx["convergence"]
    if conv:
        o.append("<h2>Convergence</h2>")
        o.append("<p>relMSE against render time on log-log axes, each point a separate render "
                 "(own seed). An unbiased Monte Carlo estimator with independent samples falls "
                 "along a line of slope −1 (grey, through the first point of "
                 f"{e(conv[0]['id'])}); a steeper slope means faster than 1/N convergence. "
                 "The slope in the legend is a least-squares fit. When the curves approach "
                 "the reference's own error (red dotted), they flatten: the reference is no "
                 "longer accurate enough to measure them.</p>")
        series = []
        for i, c in enumerate(conv):
            pts = [(p["seconds"], p["relmse"]) for p in c["points"]]
            series.append(dict(label=f"{c['id']} (slope {plain(loglog_slope(pts), 3).replace('-', '−')})",
                               colour=COLOURS[i % len(COLOURS)], dash=DASHES[i % len(DASHES)],
                               points=pts))
        first = min(conv[0]["points"], key=lambda p: p["seconds"])
        o.append(svg_loglog(series, "render time (s)", "relMSE", ref.get("floor"),
                            (first["seconds"], first["relmse"]), "plot-time"))
        o.append("<p>The same renders against samples per pixel, which no other job on the "
                 "machine can disturb (slope −1 through the first point of "
                 f"{e(conv[0]['id'])}):</p>")
        series_spp = []
        for i, c in enumerate(conv):
            pts = [(p["spp"], p["relmse"]) for p in c["points"]]
            series_spp.append(dict(label=f"{c['id']} (slope {plain(loglog_slope(pts), 3).replace('-', '−')})",
                                   colour=COLOURS[i % len(COLOURS)], dash=DASHES[i % len(DASHES)],
                                   points=pts))
        first = min(conv[0]["points"], key=lambda p: p["spp"])
        o.append(svg_loglog(series_spp, "samples per pixel", "relMSE", ref.get("floor"),
                            (first["spp"], first["relmse"]), "plot-spp",
                            "slope −1: relMSE ∝ 1/spp"))
        o.append("<table><tr><th class='l'>configuration</th><th>target s</th><th>seconds</th>"
                 "<th>spp</th><th>relMSE</th><th>1/(relMSE·s)</th></tr>")
        for c in conv:
            for p in c["points"]:
                o.append(f"<tr><td class='l'>{e(c['id'])}</td><td>{p['target']:g}</td>"
                         f"<td>{p['seconds']:.3f}</td><td>{p['spp']}</td>"
                         f"<td>{fmt(p['relmse'])}</td>"
                         f"<td>{fmt(1 / (p['relmse'] * p['seconds']))}</td></tr>")
        o.append("</table>")

    # Images.
    o.append("<h2>Images</h2>")
    o.append("<p>Each render (sRGB, clamped at 1, no tone mapping) with its error map beside "
             "it: per pixel, the mean over channels of (v − r)² / (|r| + 0.01)², the quantity "
             "whose mean is relMSE, on a log colour scale from 10⁻⁶ (dark purple) through "
             "10⁻³ (teal) to 1 and above (yellow); red marks NaN or Inf. "
             "<a href='https://en.wikipedia.org/wiki/Viridis'>viridis</a>, as "
             "<code>clpt-diff --error-map</code> draws it.</p>")
    o.append(f"<p><b>Reference</b><br><img class='px' src='{e(ref['png'])}' width='{thumb}' "
             f"height='{thumb_h}' alt='reference'></p>")
    o.append("<table class='grid'><tr><th class='l'>strategy</th>"
             + "".join(f"<th>{e(s)}</th>" for s in samplers) + "</tr>")
    by_id = {r["id"]: r for r in res}
    for sid, label, _ in strategies:
        cells = []
        for s in samplers:
            r = by_id.get(f"{sid}-{s}")
            if not r:
                cells.append("<td>–</td>")
                continue
            cells.append(
                f"<td id='img-{e(r['id'])}'><div class='pair'>"
                f"<img class='px' src='{e(r['png'])}' width='{thumb}' height='{thumb_h}' "
                f"alt='{e(r['id'])}' title='{e(r['id'])}'>"
                f"<img class='px' src='{e(r['err_png'])}' width='{thumb}' height='{thumb_h}' "
                f"alt='error map of {e(r['id'])}' title='error map of {e(r['id'])}'></div>"
                f"{r['spp']} spp, relMSE {fmt(r['relmse'])}</td>")
        o.append(f"<tr><td class='l'>{e(sid)}<br><span class='note'>{e(label)}</span></td>"
                 + "".join(cells) + "</tr>")
    o.append("</table>")

    # How to read.
    o.append("<h2>How to read this</h2><ul>")
    o.append("<li><b>relMSE</b> = mean over pixel-channels of (v − r)² / (|r| + 0.01)², "
             "from <code>clpt-diff --json</code> against the reference. It includes the "
             "reference's own error (see above), so the best configurations are measured "
             "pessimistically when their relMSE comes near it.</li>")
    o.append("<li><b>efficiency 1/(relMSE·s)</b>: the ranking. Doubling the time of an "
             "unbiased estimator halves its relMSE, so this figure is the same for any budget; "
             "twice the efficiency means the same quality in half the time.</li>")
    o.append("<li><b>mean variance</b> and <b>1/(variance·s)</b> come from clpt's "
             "<code>--stats</code>: each pixel's sample variance divided by its spp, averaged. "
             "That formula assumes independent samples. Stratified, Latin hypercube and Sobol "
             "samples are negatively correlated on purpose, so for them the true error is "
             "below this estimate: compare samplers by relMSE, not by this column.</li>")
    o.append("<li><b>seconds</b> is clpt's render time: kernel build, scene load and process "
             "start are excluded. Equal-time comparisons need an otherwise idle machine; the "
             "load average above says how busy it was, and <b>CPU s</b> (clpt's CPU time "
             "less start-up) gives a comparison that other jobs hardly disturb.</li>")
    o.append("<li>Concepts: <code>docs/concepts/</code> (hemisphere sampling, MIS, Russian "
             "roulette, stratification, QMC).</li>")
    o.append("</ul>")

    o.append("<h2>Commands</h2><p>Run in this folder, in this order "
             "(<a href='commands.txt'>commands.txt</a>; figures in "
             "<a href='results.json'>results.json</a>):</p>")
    o.append(f"<details><summary>{len(ctx['commands'])} commands</summary><pre>"
             + e("\n".join(ctx["commands"])) + "</pre></details>")
    o.append("</body></html>\n")
    path.write_text("\n".join(o), encoding="utf-8")


def check_html(path: Path, expected_rows: int) -> None:
    """The report's own check: one row per configuration, every relMSE a finite number."""
    text = path.read_text(encoding="utf-8")
    rows = re.findall(r'<tr class="config[^"]*" data-id="([^"]+)" data-relmse="([^"]*)"', text)
    if len(rows) != expected_rows or expected_rows == 0:
        raise ReportError(f"report check: {len(rows)} configuration rows in the HTML, "
                          f"expected {expected_rows}")
    bad = []
    for cid, v in rows:
        try:
            ok = math.isfinite(float(v)) and float(v) >= 0
        except ValueError:
            ok = False
        if not ok:
            bad.append(f"{cid} ({v})")
    if bad:
        raise ReportError("report check: relMSE is not a finite number for " + ", ".join(bad))
    for img in re.findall(r"<img[^>]* src='([^']+)'", text):
        if not (path.parent / html.unescape(img)).is_file():
            raise ReportError(f"report check: image {img} is missing")


# ---- main ---------------------------------------------------------------------------------


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        description="Render a scene with every estimator strategy x sampler for equal time "
                    "and write an HTML efficiency report.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Configurations are STRATEGY-SAMPLER with STRATEGY in "
               + ", ".join(s[0] for s in STRATEGIES) + " and SAMPLER in "
               + ", ".join(SAMPLERS) + ".")
    p.add_argument("--scene", default=str(REPO / "scenes" / "cornell_box.gltf"),
                   help="glTF scene [scenes/cornell_box.gltf]")
    p.add_argument("--time", type=float, help="seconds per configuration [4; --quick 0.3]")
    p.add_argument("--resolution", help="WxH [128x128; --quick 32x32]")
    p.add_argument("--reference-spp", type=int, help="reference samples per pixel [4096; --quick 2048]")
    p.add_argument("--reference", help="reuse this EXR as the reference instead of rendering one")
    p.add_argument("--out", default="report", help="output folder, replaced if it holds an "
                   "earlier report [report]")
    p.add_argument("--clpt", help="clpt binary [build/clpt]")
    p.add_argument("--clpt-diff", help="clpt-diff binary [build/clpt-diff]")
    p.add_argument("--oiiotool", default="oiiotool", help="oiiotool for EXR to PNG [oiiotool]")
    p.add_argument("--device", default="pocl", help="clpt --device SPEC [pocl]")
    p.add_argument("--max-depth", type=int, help="clpt --max-depth [clpt's default]")
    p.add_argument("--seed", type=int, default=1, help="first seed; each render gets its own [1]")
    p.add_argument("--configs", help="comma-separated STRATEGY-SAMPLER list [all strategies x "
                   "all samplers]")
    p.add_argument("--strategies", help="comma-separated strategies [all]")
    p.add_argument("--samplers", help="comma-separated samplers [all]")
    p.add_argument("--convergence", help="comma-separated configurations for the convergence "
                   "plot, or 'none' [" + ",".join(DEFAULT_CONVERGENCE) + "]")
    p.add_argument("--quick", action="store_true", help="tiny resolution and time, five "
                   "configurations (smoke test, well under a minute)")
    p.add_argument("--backend", choices=["auto", "module", "process"], default="auto",
                   help="render through the clpt Python module (in-process) or a clpt process per "
                        "render [auto: the module when it imports]")
    p.add_argument("--keep-temp", action="store_true", help="keep the temporary folder on failure")
    a = p.parse_args(argv)
    q = QUICK if a.quick else {}
    a.time = a.time if a.time is not None else q.get("time", 4.0)
    a.resolution = a.resolution or q.get("resolution", "128x128")
    a.reference_spp = a.reference_spp or q.get("reference_spp", 4096)
    m = re.fullmatch(r"(\d+)x(\d+)", a.resolution)
    if not m or int(m[1]) < 1 or int(m[2]) < 1:
        p.error("--resolution must be WxH, e.g. 128x128")
    a.width, a.height = int(m[1]), int(m[2])
    if a.time <= 0:
        p.error("--time must be positive")
    if a.reference_spp < 2:
        p.error("--reference-spp must be at least 2")
    if a.configs:
        ids = [c.strip() for c in a.configs.split(",") if c.strip()]
    elif a.quick and not (a.strategies or a.samplers):
        ids = list(q["configs"])
    else:
        strats = a.strategies.split(",") if a.strategies else [s[0] for s in STRATEGIES]
        samps = a.samplers.split(",") if a.samplers else SAMPLERS
        ids = [f"{st.strip()}-{sa.strip()}" for st in strats for sa in samps]
    a.config_ids = ids
    if a.convergence == "none":
        a.conv_ids = []
    elif a.convergence:
        a.conv_ids = [c.strip() for c in a.convergence.split(",") if c.strip()]
    else:
        a.conv_ids = [c for c in (q.get("convergence") or DEFAULT_CONVERGENCE) if c in ids]
    a.fractions = q.get("fractions", FRACTIONS)
    return a


def prepare_out(out: Path) -> None:
    if out.exists():
        if not out.is_dir():
            raise ReportError(f"--out {out} exists and is not a folder")
        if any(out.iterdir()) and not (out / MARKER).exists():
            raise ReportError(f"--out {out} is a non-empty folder that this script did not "
                              "write; choose another or empty it")
    out.parent.mkdir(parents=True, exist_ok=True)


def publish(tmp: Path, out: Path) -> None:
    """Renames the finished report into place, replacing an earlier one."""
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        old.rmdir()
        out.rename(old)
    tmp.rename(out)
    if old:
        shutil.rmtree(old, ignore_errors=True)


def build_report(a: argparse.Namespace, run: Runner, tmp: Path) -> dict:
    t_start = time.monotonic()
    load_before = os.getloadavg()
    scene = str(Path(a.scene).resolve())
    if not Path(scene).is_file():
        raise ReportError(f"scene {a.scene} not found")
    configs = make_configs(a.config_ids)
    conv_configs = make_configs(a.conv_ids) if a.conv_ids else []
    for d in ("renders", "images", "stats", "diff", "convergence"):
        (tmp / d).mkdir()
    common = ["--resolution", f"{a.width}x{a.height}"]
    if a.max_depth is not None:
        common += ["--max-depth", str(a.max_depth)]
    seed = a.seed

    # Warm-up: the first run builds the kernel (when the cache is cold); the second measures
    # the CPU time of a run that renders next to nothing (process start, PoCL, scene,
    # cached kernel), which is taken off every render's CPU time.
    for k in range(2):
        run.render(scene, common + ["--spp", "1"], "renders/startup.exr", "stats/startup.json",
                   "warm-up", 300)
    startup_cpu = run.last_cpu
    log(f"start-up: {startup_cpu:.2f} CPU s per clpt run")

    # (a) Reference.
    ref: dict = {}
    ref_args = None  # how to render the reference again (PNGs without oiiotool)
    if a.reference:
        src = Path(a.reference).resolve()
        if not src.is_file():
            raise ReportError(f"--reference {a.reference} not found")
        shutil.copyfile(src, tmp / "reference.exr")
        info = run.diff("reference.exr", "reference.exr", None, "the reference with itself")
        rw, rh = info["image"]["width"], info["image"]["height"]
        if (rw, rh) != (a.width, a.height):
            raise ReportError(f"--reference {a.reference} is {rw}x{rh}, the report renders "
                              f"{a.width}x{a.height} (use --resolution {rw}x{rh})")
        spp = info["image"].get("spp")
        ref.update(description=f"<code>{html.escape(a.reference)}</code> (given; "
                               f"{spp if spp else 'unknown'} spp)",
                   floor=None, floor_text="unknown (reference given with --reference)")
        log(f"reference: {a.reference}")
    elif run.oiiotool:
        half = a.reference_spp // 2
        log(f"reference: 2 x {half} spp at {a.width}x{a.height} ...")
        secs = 0.0
        halves = []
        for k in range(2):
            st = run.render(scene, common + ["--spp", str(half), "--seed", str(1000001 + k)],
                            f"renders/reference-{k}.exr", f"stats/reference-{k}.json",
                            f"reference half {k}", None)
            secs += st["render_seconds"]
            halves.append(f"renders/reference-{k}.exr")
        d = run.diff(halves[0], halves[1], None, "the reference halves")
        floor = num(d["relmse"]) / 4
        run.run([run.oiiotool, halves[0], halves[1], "--add", "--mulc", "0.5",
                 "--attrib:type=int", "clpt:spp", str(2 * half), "-d", "float",
                 "-o", "reference.exr"], "averaging the reference halves", timeout=120)
        ref.update(description=f"{2 * half} spp, default estimator, independent sampler, two "
                               f"halves of {half} spp (seeds 1000001, 1000002) averaged; "
                               f"{secs:.1f} s",
                   floor=floor,
                   floor_text=f"relMSE ≈ {fmt(floor)}: a quarter of the relMSE between the "
                              f"two halves ({fmt(num(d['relmse']))}), which are independent "
                              "estimates of the same image. Every relMSE below includes it.")
        log(f"reference: {2 * half} spp in {secs:.1f} s; its own relMSE ~ {floor:.3g}")
    else:  # without oiiotool nothing can average two EXRs: one piece, error unknown
        log(f"reference: {a.reference_spp} spp at {a.width}x{a.height} ...")
        ref_args = common + ["--spp", str(a.reference_spp), "--seed", "1000001"]
        st = run.render(scene, ref_args, "reference.exr", "stats/reference.json", "reference",
                        None)
        ref.update(description=f"{a.reference_spp} spp, default estimator, independent "
                               f"sampler, seed 1000001; {st['render_seconds']:.1f} s",
                   floor=None, floor_text="not estimated (needs oiiotool)")
    if not run.oiiotool and ref_args is None:
        raise ReportError("--reference needs oiiotool to show the reference as a PNG")
    run.to_png("reference.exr", "images/reference.png", "the reference", scene, ref_args)
    ref["png"] = "images/reference.png"
    ref_exr = "reference.exr"

    def evaluate(c: Config, name: str, folder: str, what: str, images: bool,
                 seconds: float, spp_target: int | None) -> dict:
        nonlocal seed
        seed += 1
        exr = f"{folder}/{name}.exr"
        stats = f"stats/{name}.json"
        if spp_target:
            # About equal time: the spp the independent sampler reached. The --time cap
            # only stops a runaway render; a warning says if it was hit.
            budget = ["--spp", str(spp_target), "--time", f"{3 * seconds + 1:g}"]
        else:
            budget = ["--time", f"{seconds:g}"]
        st = run.render(scene, common + c.options() + budget + ["--seed", str(seed)], exr,
                        stats, what, 10 * seconds + 120)
        if spp_target and st["spp"] < spp_target:
            log(f"warning: {what} reached {st['spp']} of {spp_target} spp before its time cap")
        d = run.diff(exr, ref_exr, f"images/{name}_err.png" if images else None, what)
        (tmp / "diff" / f"{name}.json").write_text(json.dumps(d, indent=1))
        if images:
            run.to_png(exr, f"images/{name}.png", what, scene,
                       common + c.options() + ["--spp", str(st["spp"]), "--seed", str(seed)])
        relmse = num(d["relmse"])
        secs = float(st["render_seconds"])
        cpu = max(1e-3, st["process_cpu_seconds"] - startup_cpu)
        z = d.get("z_test")
        return dict(id=c.id, strategy=c.strategy, sampler=c.sampler, label=c.label,
                    options=c.options(), seed=seed, spp=int(st["spp"]),
                    spp_target=spp_target, seconds=secs,
                    mean_variance=num(st.get("mean_variance")),
                    eff_variance=num(st.get("efficiency")),
                    relmse=relmse, mse=num(d.get("mse")), smape=num(d.get("smape")),
                    eff_relmse=(1.0 / (relmse * secs)) if relmse > 0 else float("inf"),
                    cpu_seconds=cpu,
                    eff_cpu=(1.0 / (relmse * cpu)) if relmse > 0 else float("inf"),
                    z_pass=(z or {}).get("pass_fraction"),
                    dropped=int(st.get("dropped_samples", 0)),
                    paths_per_second=num(st.get("camera_paths_per_second")),
                    device=st.get("device", {}).get("name", "?"),
                    exr=exr, png=f"images/{name}.png", err_png=f"images/{name}_err.png")

    # (b) Equal-time renders.
    results = []
    spp_of: dict[tuple[str, float], int] = {}
    n = len(configs)
    # Stratified and lhs run to a sample count, about 1.6x the budget on PoCL.
    est = (sum((1.6 if c.sampler in NEEDS_SPP else 1.0) * a.time + 0.5 for c in configs)
           + len(conv_configs) * (sum(a.fractions) * a.time + 0.5 * len(a.fractions)))
    log(f"{n} configurations x {a.time:g} s, then {len(conv_configs)} convergence series: "
        f"about {est / 60:.1f} min more")
    for i, c in enumerate(configs, 1):
        target = None
        if c.sampler in NEEDS_SPP:
            indep = spp_of[(c.strategy, 1.0)]
            target = stratified_spp(indep) if c.sampler == "stratified" else indep
        r = evaluate(c, c.id, "renders", c.id, True, a.time, target)
        if c.sampler == "independent":
            spp_of[(c.strategy, 1.0)] = r["spp"]
        results.append(r)
        log(f"[{i}/{n}] {c.id:<22} {r['spp']:>6} spp {r['seconds']:6.2f} s  relMSE "
            f"{r['relmse']:.4g}  1/(relMSE s) {r['eff_relmse']:.4g}")
        if not math.isfinite(r["relmse"]):
            raise ReportError(f"{c.id}: relMSE is {r['relmse']} (clpt-diff found no finite "
                              f"pixels to compare; see diff/{c.id}.json)")
        if r["dropped"]:
            log(f"warning: {c.id} dropped {r['dropped']} NaN/Inf samples")

    # (d) Convergence.
    by_id = {r["id"]: r for r in results}
    convergence = []
    for c in conv_configs:
        pts = []
        for f in a.fractions:
            target = None
            if c.sampler in NEEDS_SPP:
                indep = spp_of.get((c.strategy, f))
                if indep is None:
                    indep = max(1, round(spp_of.get((c.strategy, 1.0), 0) * f))
                    if indep <= 1:
                        raise ReportError(f"convergence of {c.id} needs {c.strategy}-independent")
                target = stratified_spp(indep) if c.sampler == "stratified" else indep
            name = f"{c.id}_t{f:g}"
            r = evaluate(c, name, "convergence", f"{c.id} at {a.time * f:g} s", False,
                         a.time * f, target)
            if c.sampler == "independent":
                spp_of[(c.strategy, f)] = r["spp"]
            if not math.isfinite(r["relmse"]):
                raise ReportError(f"{name}: relMSE is not finite")
            pts.append(dict(target=a.time * f, seconds=r["seconds"], spp=r["spp"],
                            relmse=r["relmse"]))
        full = by_id.get(c.id)
        if full is None:
            target = None
            if c.sampler in NEEDS_SPP:
                indep = spp_of[(c.strategy, 1.0)]
                target = stratified_spp(indep) if c.sampler == "stratified" else indep
            full = evaluate(c, f"{c.id}_t1", "convergence", c.id, False, a.time, target)
        pts.append(dict(target=a.time, seconds=full["seconds"], spp=full["spp"],
                        relmse=full["relmse"]))
        convergence.append(dict(id=c.id, points=pts))
        log(f"convergence {c.id}: slope "
            f"{loglog_slope([(p['seconds'], p['relmse']) for p in pts]):.3f}")

    load_after = os.getloadavg()
    cpus = os.cpu_count()
    versions = f"{tool_version([run.clpt])}; clpt-diff {tool_version([run.clpt_diff]).split()[-1]}; " \
               f"{'oiiotool ' + tool_version([run.oiiotool]) if run.oiiotool else 'no oiiotool'}"
    ctx = dict(
        results=results, convergence=convergence, reference=ref,
        scene=os.path.relpath(scene, REPO) if scene.startswith(str(REPO)) else scene,
        scene_name=Path(scene).name, width=a.width, height=a.height, time=a.time,
        device=results[0]["device"] if results else "?",
        versions=versions,
        machine=f"{cpus} CPUs; load average {load_before[0]:.2f} at the start, "
                f"{load_after[0]:.2f} at the end (1-minute); a clpt run's start-up costs "
                f"{startup_cpu:.2f} CPU s (taken off the CPU seconds below)",
        date=datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        wall=time.monotonic() - t_start, commands=run.commands)
    return ctx


def main(argv: list[str]) -> int:
    a = parse_args(argv)

    def terminate(signum, frame):  # SIGTERM: clean up as for Ctrl-C
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, terminate)
    tmp = None
    try:
        clpt = find_tool(a.clpt, REPO / "build" / "clpt", "clpt",
                         "build it with cmake --build build, or pass --clpt")
        clpt_diff = find_tool(a.clpt_diff, REPO / "build" / "clpt-diff", "clpt-diff",
                              "build it with cmake --build build, or pass --clpt-diff")
        try:
            oiiotool = find_tool(a.oiiotool, Path("oiiotool"), "oiiotool", "")
        except ReportError:
            oiiotool = None
        if oiiotool and not oiiotool_usable(oiiotool):
            oiiotool = None
        if not oiiotool:
            log("efficiency_report: oiiotool (openimageio-tools, see scripts/install-deps.sh) "
                "is missing or cannot convert to sRGB: PNGs are rendered again by clpt, and "
                "the reference's own error is not estimated")
        out = Path(a.out).resolve()
        prepare_out(out)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.tmp-", dir=out.parent))
        run = Runner(clpt, clpt_diff, oiiotool, a.device, tmp)
        run.module = load_module(a.backend)
        log(f"efficiency_report: renders run {'in-process (clpt module)' if run.module else 'as clpt processes'}")
        t0 = time.monotonic()
        ctx = build_report(a, run, tmp)
        (tmp / "commands.txt").write_text("\n".join(run.commands) + "\n")
        (tmp / "results.json").write_text(json.dumps(
            {k: ctx[k] for k in ("results", "convergence", "reference", "scene", "width",
                                 "height", "time", "device", "versions", "machine", "date",
                                 "wall")}, indent=1, default=str) + "\n")
        (tmp / MARKER).write_text("written by scripts/efficiency_report.py\n")
        ctx["wall"] = time.monotonic() - t0
        write_html(tmp / "index.html", ctx)
        check_html(tmp / "index.html", len(ctx["results"]))
        publish(tmp, out)
        tmp = None
        ranked = sorted(ctx["results"], key=lambda r: -r["eff_relmse"])
        log(f"wrote {out / 'index.html'} in {ctx['wall']:.0f} s; best: "
            + ", ".join(f"{r['id']} {r['eff_relmse']:.4g}" for r in ranked[:3]))
        return 0
    except ReportError as e:
        log(f"efficiency_report: error: {e}")
        return 1
    except KeyboardInterrupt:
        log("efficiency_report: interrupted; no report written")
        return 130
    finally:
        if tmp is not None and tmp.exists():
            if a.keep_temp:
                log(f"efficiency_report: kept the unfinished report in {tmp}")
            else:
                shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
