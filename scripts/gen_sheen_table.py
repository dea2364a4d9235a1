#!/usr/bin/env python3
"""Writes kernels/bsdf/sheen_table.h: the directional albedos of KHR_materials_sheen's lobe
that kernels/bsdf/sheen.cl looks up.

The lobe (the extension's implementation notes): the "Charlie" distribution of Conty and
Kulla 2017, D(h) = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi), a = roughness^2, with their fitted
Lambda in G2 = 1 / (1 + Lambda(wo) + Lambda(wi)):
    f(wo, wi) = D(h) G2 / (4 cos_o cos_i)       (sheen colour 1)
Its albedo E(cos_o) = integral f cos_i dwi exceeds 1 at grazing views of smooth sheens (the
fitted Lambda is not a Smith Lambda of D: E = 2.3 at cos 0.02, roughness 0.05), so clpt's lobe
is capped, symmetrically so that it stays reciprocal:
    f'(wo, wi) = f(wo, wi) / max(1, E(cos_o), E(cos_i))
whose albedo E'(cos_o) <= E(cos_o) / max(1, E(cos_o)) <= 1. The base under the sheen is scaled
by min(1 - m E'(cos_o), 1 - m E'(cos_i)) (m the sheen colour's largest component), so that the
two together reflect at most 1.

Two tables, E and E', each SHEEN_TABLE_R rows of SHEEN_TABLE_MU floats: row j for roughness
r_j = R_MIN + (1 - R_MIN) (j / (SHEEN_TABLE_R - 1))^2 (roughness below R_MIN reads as R_MIN),
column i for cos = (i / (SHEEN_TABLE_MU - 1))^2: both dense where E changes fastest, at
grazing angles and small roughness. Bilinear between nodes in (sqrt(cos), sqrt(r - R_MIN)).
E' is integrated with E read through the same lookup the kernel uses, so the cap in E' is
the one the kernel applies. Where the cap switches on (E crossing 1 at small roughness and
grazing angles) E' has a kink that bilinear interpolation cuts by up to 0.012; since E'
scales the base (and an E' read too low would let the two layers reflect more than 1), the
nodes of every cell whose corners reach E > 0.8 are then raised by the largest shortfall of
the lookup against the integral at a 3 x 3 grid inside the cell. Elsewhere the lookup is
within 4e-4 of the integral (--check).

Quadrature: the half vector is importance sampled by D(h) cos(theta_h), whose inverse CDF is
sin(theta_h) = u^(a / (2a + 1)); midpoint rules in u (1024) and in the azimuth (512 over
[0, pi]: the integrand is even in it). tests/sheen_test.cpp checks both tables against the
kernel's own lobe by Monte Carlo.

    /usr/bin/python3 scripts/gen_sheen_table.py kernels/bsdf/sheen_table.h   (needs numpy; ~5 min)
    /usr/bin/python3 scripts/gen_sheen_table.py --check kernels/bsdf/sheen_table.h
"""
import multiprocessing
import re
import sys

import numpy as np

N_MU, N_R = 64, 32
R_MIN = 0.03
NU, NPHI = 1024, 512
MU_MIN = 1e-4  # the grazing column is integrated here (E grows without bound as cos -> 0)


def roughness(j):
    return R_MIN + (1.0 - R_MIN) * (j / (N_R - 1)) ** 2


def cosine(i):
    return max((i / (N_MU - 1)) ** 2, MU_MIN)


def lambda_fit(c, a):
    """Conty and Kulla's fitted Lambda of the Charlie distribution (the extension's l())."""
    t = (1.0 - a) ** 2
    A = 21.5473 + (25.3245 - 21.5473) * t
    B = 3.82987 + (3.32435 - 3.82987) * t
    C = 0.19823 + (0.16801 - 0.19823) * t
    D = -1.97760 + (-1.27393 + 1.97760) * t
    E = -4.32054 + (-4.85967 + 4.32054) * t

    def l(x):
        return A / (1.0 + B * np.power(x, C)) + D * x + E

    c = np.abs(c)
    return np.where(c < 0.5, np.exp(l(c)), np.exp(2.0 * l(0.5) - l(1.0 - c)))


def lookup(table, mu, r):
    """The kernel's bilinear lookup (sheen.cl sheen_albedos), vectorised over mu."""
    x = np.sqrt(np.clip(mu, 0.0, 1.0)) * (N_MU - 1)
    y = np.sqrt(np.clip((r - R_MIN) / (1.0 - R_MIN), 0.0, 1.0)) * (N_R - 1)
    i = np.minimum(x.astype(int), N_MU - 2)
    j = min(int(y), N_R - 2)
    fx, fy = x - i, y - j
    row0 = table[j][i] * (1 - fx) + table[j][i + 1] * fx
    row1 = table[j + 1][i] * (1 - fx) + table[j + 1][i + 1] * fx
    return row0 * (1 - fy) + row1 * fy


def albedo(mu, r, cap_table=None):
    a = r * r
    u = (np.arange(NU) + 0.5) / NU
    phi = (np.arange(NPHI) + 0.5) / NPHI * np.pi
    U, P = np.meshgrid(u, phi, indexing="ij")
    s = np.power(U, a / (2.0 * a + 1.0))
    c = np.sqrt(np.maximum(0.0, 1.0 - s * s))
    wo = (np.sqrt(1.0 - mu * mu), 0.0, mu)
    wo_h = wo[0] * s * np.cos(P) + wo[2] * c
    wi_z = 2.0 * wo_h * c - mu
    ok = (wo_h > 0.0) & (wi_z > 0.0) & (c > 0.0)
    wi_z = np.where(ok, wi_z, 1.0)
    g2 = 1.0 / (1.0 + lambda_fit(mu, a) + lambda_fit(wi_z, a))
    # E = integral [D cos_h dw_h] G2 (wo.h) / (cos_o cos_h): dw_i = 4 (wo.h) dw_h.
    val = g2 * wo_h / (mu * np.where(ok, c, 1.0))
    if cap_table is not None:
        e_o = lookup(cap_table, np.array([mu]), r)[0]
        val = val / np.maximum(1.0, np.maximum(e_o, lookup(cap_table, wi_z, r)))
    return float(np.where(ok, val, 0.0).mean())


def _row(args):
    j, cap_table = args
    return [albedo(cosine(i), roughness(j), cap_table) for i in range(N_MU)]


def table(cap_table=None):
    with multiprocessing.Pool() as pool:
        return pool.map(_row, [(j, cap_table) for j in range(N_R)])


def c_rows(e, e_capped):
    """The two tables interleaved, (E, E') per node, so that one lookup reads both."""
    lines = ["__constant float sheen_albedo_table[SHEEN_TABLE_R * SHEEN_TABLE_MU * 2] = {"]
    for j in range(N_R):
        lines.append(f"    /* roughness {roughness(j):.6f}: (E, E') at cos (i / {N_MU - 1})^2 */")
        for k in range(0, N_MU, 4):
            lines.append("    " + " ".join(f"{e[j][i]:.6e}f, {e_capped[j][i]:.6e}f,"
                                           for i in range(k, k + 4)))
    lines.append("};")
    return "\n".join(lines)


def _shortfall(args):
    """The largest amount by which the lookup of E' falls short of the integral inside cell
    (i, j), at a 3 x 3 grid of points (in the lookup's coordinates)."""
    i, j, e, e_capped = args
    worst = 0.0
    for a in (0.25, 0.5, 0.75):
        for b in (0.25, 0.5, 0.75):
            mu = ((i + a) / (N_MU - 1)) ** 2
            r = R_MIN + (1.0 - R_MIN) * ((j + b) / (N_R - 1)) ** 2
            looked = float(lookup(e_capped, np.array([mu]), r)[0])
            worst = max(worst, albedo(max(mu, MU_MIN), r, e) - looked)
    return worst


def conservative(e, e_capped):
    """E' with the nodes of the cells near the cap raised so that the lookup does not fall
    short of the integral there (see the notes above). Returns the table and the largest raise."""
    e, out = np.array(e), np.array(e_capped)
    cells = [(i, j) for j in range(N_R - 1) for i in range(N_MU - 1)
             if max(e[j][i], e[j][i + 1], e[j + 1][i], e[j + 1][i + 1]) > 0.8]
    with multiprocessing.Pool() as pool:
        short = pool.map(_shortfall, [(i, j, e, out) for i, j in cells])
    raised = np.zeros_like(out)
    for (i, j), d in zip(cells, short):
        if d > 0.0:
            for jj, ii in ((j, i), (j, i + 1), (j + 1, i), (j + 1, i + 1)):
                raised[jj][ii] = max(raised[jj][ii], d)
    return (out + raised).tolist(), float(raised.max()), len(cells)


def read_tables(text):
    """(E, E') as written by header()."""
    body = text.split("sheen_albedo_table[SHEEN_TABLE_R * SHEEN_TABLE_MU * 2] = {")[1].split("};")[0]
    body = re.sub(r"/\*.*?\*/", "", body)
    v = np.array([float(x.rstrip("f")) for x in body.replace(",", " ").split()]).reshape(N_R, N_MU, 2)
    return v[:, :, 0], v[:, :, 1]


def header(e, e_capped, raise_max):
    return f"""/* Generated by scripts/gen_sheen_table.py: do not edit. The directional albedos of
 * KHR_materials_sheen's Charlie lobe (sheen colour 1), read by kernels/bsdf/sheen.cl, as
 * (E, E') pairs per node:
 *   E   E(cos, r), the lobe as the extension defines it (exceeds 1 when grazing);
 *   E'  E'(cos, r), the lobe divided by max(1, E(cos_o), E(cos_i)), as clpt uses it, its
 *       nodes near the cap raised by up to SHEEN_E_CAPPED_RAISE so that the lookup does not
 *       fall short of the integral (the script's notes).
 * Row j: roughness SHEEN_R_MIN + (1 - SHEEN_R_MIN) (j / (SHEEN_TABLE_R - 1))^2; column i:
 * cos = (i / (SHEEN_TABLE_MU - 1))^2. */
#ifndef CLPT_BSDF_SHEEN_TABLE_H
#define CLPT_BSDF_SHEEN_TABLE_H

#define SHEEN_TABLE_MU {N_MU}
#define SHEEN_TABLE_R {N_R}
#define SHEEN_R_MIN {R_MIN}f
#define SHEEN_E_CAPPED_RAISE {raise_max:.6f}f

{c_rows(e, e_capped)}

#endif
"""


def check(path):
    """The lookup of E' against the capped lobe's albedo integrated anew, off the nodes."""
    e, e_capped = read_tables(open(path).read())
    rng = np.random.default_rng(1)
    short, excess = 0.0, 0.0
    for _ in range(64):
        mu, r = rng.uniform(0.0, 1.0) ** 2, max(rng.uniform(0.0, 1.0) ** 2, R_MIN)
        direct = albedo(max(mu, MU_MIN), r, e)
        looked = float(lookup(e_capped, np.array([mu]), r)[0])
        short, excess = max(short, direct - looked), max(excess, looked - direct)
        print(f"cos {mu:.4f} r {r:.3f}: capped albedo {direct:.4f}, lookup {looked:.4f}, {looked - direct:+.4f}")
    print(f"largest shortfall of the lookup {short:.4f}, largest excess {excess:.4f}")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        return check(sys.argv[2])
    if len(sys.argv) != 2:
        sys.exit("usage: gen_sheen_table.py [--check] OUT.h")
    e = table()
    e_capped, raise_max, cells = conservative(e, table(np.array(e)))
    text = header(e, e_capped, raise_max)
    with open(sys.argv[1], "w") as f:
        f.write(text)
    worst = max(max(row) for row in e)
    print(f"wrote {sys.argv[1]}: max E {worst:.3f}, max E' {max(max(r) for r in e_capped):.4f}; "
          f"{cells} cells checked near the cap, nodes raised by up to {raise_max:.4f}")


if __name__ == "__main__":
    main()
