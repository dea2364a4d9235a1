#!/usr/bin/env python3
"""Writes the 1M-triangle benchmark scene of issue 21, deterministically, as one .glb:
25 displaced spheres (a 5 x 5 grid, 40 000 triangles each: 200 segments x 101 rings) on a
floor, lit by one quad light above them, seen by one camera. Every material is Lambertian for
clpt and for Blender's importer alike (metallic 0, roughness 1, KHR_materials_specular with
specularFactor 0 and specularColorFactor 0), so scripts/bench_cycles.py compares like with like.

    python3 scripts/make_spheres_1m.py bench-out/spheres_1m.glb

Too large for scenes/ (about 37 MB), so it is generated where it is needed. Python 3
standard library only (about 15 s).
"""
import json
import math
import struct
import sys

SEGMENTS, RINGS = 200, 101  # per sphere: 2 * SEGMENTS * (RINGS - 1) triangles = 40 000
GRID = 5


def sphere(cx, cz, radius, phase):
    """Positions, normals and indices of one displaced UV sphere standing on y = 0."""
    pos, nrm, idx = [], [], []
    for r in range(RINGS + 1):
        theta = math.pi * r / RINGS
        for s in range(SEGMENTS):
            phi = 2.0 * math.pi * s / SEGMENTS
            d = (math.sin(theta), math.cos(theta))
            n = (d[0] * math.cos(phi), d[1], d[0] * math.sin(phi))
            bump = 1.0 + 0.06 * math.sin(7 * phi + phase) * math.sin(9 * theta + 2 * phase)
            rr = radius * bump
            pos.append((cx + rr * n[0], radius + rr * n[1], cz + rr * n[2]))
            nrm.append(n)
    for r in range(RINGS):
        for s in range(SEGMENTS):
            a = r * SEGMENTS + s
            b = r * SEGMENTS + (s + 1) % SEGMENTS
            c, d = a + SEGMENTS, b + SEGMENTS
            if r > 0:
                idx.append((a, b, c))  # counter-clockwise seen from outside
            if r < RINGS - 1:
                idx.append((b, d, c))
    return pos, nrm, idx


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    out = sys.argv[1]
    meshes = []  # (positions, normals, indices, material)
    for i in range(GRID):
        for j in range(GRID):
            p, n, t = sphere(-2.0 + i, -2.0 + j, 0.4, 0.7 * (i * GRID + j))
            meshes.append((p, n, t, 0))
    floor = [(-4.0, 0.0, -4.0), (-4.0, 0.0, 4.0), (4.0, 0.0, 4.0), (4.0, 0.0, -4.0)]
    meshes.append((floor, [(0.0, 1.0, 0.0)] * 4, [(0, 1, 2), (0, 2, 3)], 1))
    light = [(-1.0, 4.0, -1.0), (1.0, 4.0, -1.0), (1.0, 4.0, 1.0), (-1.0, 4.0, 1.0)]
    meshes.append((light, [(0.0, -1.0, 0.0)] * 4, [(0, 1, 2), (0, 2, 3)], 2))

    blob = bytearray()
    views, accessors, prims = [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for p, n, t, material in meshes:
        lo = [min(v[k] for v in p) for k in range(3)]
        hi = [max(v[k] for v in p) for k in range(3)]
        vp = add_view(struct.pack(f"<{3 * len(p)}f", *[c for v in p for c in v]), 34962)
        vn = add_view(struct.pack(f"<{3 * len(n)}f", *[c for v in n for c in v]), 34962)
        vi = add_view(struct.pack(f"<{3 * len(t)}I", *[c for tri in t for c in tri]), 34963)
        accessors += [
            {"bufferView": vp, "componentType": 5126, "count": len(p), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": vn, "componentType": 5126, "count": len(n), "type": "VEC3"},
            {"bufferView": vi, "componentType": 5125, "count": 3 * len(t), "type": "SCALAR"},
        ]
        a = len(accessors) - 3
        prims.append({"attributes": {"POSITION": a, "NORMAL": a + 1}, "indices": a + 2, "material": material})

    lambert = {"KHR_materials_specular": {"specularFactor": 0.0, "specularColorFactor": [0.0, 0.0, 0.0]}}

    def material(name, color, emission=None):
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0],
             "metallicFactor": 0.0, "roughnessFactor": 1.0}, "extensions": json.loads(json.dumps(lambert))}
        if emission:
            m["emissiveFactor"] = [1.0, 1.0, 1.0]
            m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": emission}
        return m

    gltf = {
        "asset": {"version": "2.0", "generator": "clpt scripts/make_spheres_1m.py"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(prims) + 1))}],
        "nodes": [{"mesh": k} for k in range(len(prims))] + [
            {"camera": 0, "translation": [0.0, 3.2, 6.0],
             "rotation": [-0.2588190, 0.0, 0.0, 0.9659258]}],  # 30 degrees down
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "meshes": [{"primitives": [p]} for p in prims],
        "materials": [material("spheres", (0.7, 0.7, 0.7)), material("floor", (0.5, 0.5, 0.5)),
                      material("light", (0.0, 0.0, 0.0), emission=20.0)],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    js = json.dumps(gltf, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    while len(blob) % 4:
        blob.append(0)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(blob)))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(blob), 0x004E4942) + blob)
    triangles = sum(len(m[2]) for m in meshes)
    print(f"{out}: {triangles} triangles, {len(blob) + len(js)} bytes")


if __name__ == "__main__":
    main()
