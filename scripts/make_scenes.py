#!/usr/bin/env python3
"""Generate clpt's reference glTF 2.0 scenes, deterministically.

    python3 scripts/make_scenes.py            # writes scenes/cornell_box.gltf,
                                              # scenes/cornell_ceiling.gltf, scenes/furnace.gltf,
                                              # scenes/caustic.gltf, scenes/indirect.gltf,
                                              # scenes/door_ajar.gltf, scenes/glass_room.gltf,
                                              # scenes/glass_table.gltf
    python3 scripts/make_scenes.py --out DIR  # writes them into DIR instead

Python 3.11 standard library only. Each scene is a single .gltf file whose one buffer is
embedded as a base64 `data:` URI. Every file is re-read and checked after it is written
(see validate()); a failed check raises AssertionError.

clpt conventions (host/scene/scene.h): right-handed, +Y up, cameras look down -Z, metres.
Counter-clockwise winding is the front face. Emitted radiance (W/m^2/sr, linear Rec.709) is
emissiveFactor x KHR_materials_emissive_strength.emissiveStrength; baseColorFactor is the
diffuse albedo (metallicFactor 0, roughnessFactor 1, KHR_materials_specular specularFactor 0:
no specular coat, so the surfaces are exactly Lambertian and the closed forms hold). The one
exception is the caustic benchmark's glass sphere: KHR_materials_transmission 1,
KHR_materials_ior 1.5, roughnessFactor 0 (smooth), default specular.

See scenes/README.md for what each scene is and what it is for.
"""

from __future__ import annotations

import argparse
import base64
import json
import math
import os
import struct
import sys

# glTF enums
FLOAT = 5126
UNSIGNED_SHORT = 5123
UNSIGNED_INT = 5125
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
TRIANGLES = 4

COMPONENT_SIZE = {FLOAT: 4, UNSIGNED_SHORT: 2, UNSIGNED_INT: 4, 5120: 1, 5121: 1, 5122: 2}
TYPE_COUNT = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
EMISSIVE_STRENGTH = "KHR_materials_emissive_strength"
SPECULAR = "KHR_materials_specular"
TRANSMISSION = "KHR_materials_transmission"
IOR = "KHR_materials_ior"
DATA_URI_PREFIX = "data:application/octet-stream;base64,"


# ---------------------------------------------------------------------------------------------
# small vector helpers (tuples of floats)

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    assert n > 0.0, "cannot normalize a zero vector"
    return (a[0] / n, a[1] / n, a[2] / n)


def f32(x):
    """x rounded to the nearest float32, as it will be stored in the buffer."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def tri_normal(p0, p1, p2):
    """Unit geometric normal of the counter-clockwise triangle p0 p1 p2."""
    return normalize(cross(sub(p1, p0), sub(p2, p0)))


# ---------------------------------------------------------------------------------------------
# glTF document builder

class Mesh:
    """One indexed triangle list with per-vertex normals and one material."""

    def __init__(self, name, material):
        self.name = name
        self.material = material
        self.positions = []
        self.normals = []
        self.triangles = []

    def add_vertex(self, p, n):
        self.positions.append(tuple(float(c) for c in p))
        self.normals.append(normalize(n))
        return len(self.positions) - 1

    def add_flat_triangle(self, p0, p1, p2):
        """Counter-clockwise triangle with its own three vertices, normals = face normal."""
        n = tri_normal(p0, p1, p2)
        i0 = self.add_vertex(p0, n)
        i1 = self.add_vertex(p1, n)
        i2 = self.add_vertex(p2, n)
        self.triangles.append((i0, i1, i2))


class Document:
    def __init__(self, generator):
        self.gltf = {
            "asset": {"version": "2.0", "generator": generator},
            "extensionsUsed": [EMISSIVE_STRENGTH, SPECULAR],
            "scene": 0,
            "scenes": [{"name": "Scene", "nodes": []}],
            "nodes": [],
            "cameras": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.blob = bytearray()
        self.material_index = {}

    # -- materials ----------------------------------------------------------------------------
    def add_material(self, name, base_color, emission=(0.0, 0.0, 0.0), double_sided=True):
        """emission is the emitted radiance; it is split into emissiveFactor (max component 1)
        and KHR_materials_emissive_strength.emissiveStrength (the magnitude)."""
        m = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [float(c) for c in base_color] + [1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
            },
            "doubleSided": bool(double_sided),
            "extensions": {SPECULAR: {"specularFactor": 0.0}},  # Lambertian: no coat
        }
        strength = max(emission)
        if strength > 0.0:
            m["emissiveFactor"] = [c / strength for c in emission]
            m["extensions"][EMISSIVE_STRENGTH] = {"emissiveStrength": float(strength)}
        self.material_index[name] = len(self.gltf["materials"])
        self.gltf["materials"].append(m)
        return self.material_index[name]

    def use_extension(self, name):
        if name not in self.gltf["extensionsUsed"]:
            self.gltf["extensionsUsed"].append(name)

    def add_glass_material(self, name, ior, double_sided=False):
        """Smooth clear dielectric: KHR_materials_transmission 1, KHR_materials_ior, white base,
        metallic 0, roughness 0 (a Dirac reflection and refraction). No KHR_materials_specular:
        glass keeps the default specular 1, i.e. the full Fresnel reflection."""
        m = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.0,
            },
            "doubleSided": bool(double_sided),
            "extensions": {TRANSMISSION: {"transmissionFactor": 1.0}, IOR: {"ior": float(ior)}},
        }
        self.use_extension(TRANSMISSION)
        self.use_extension(IOR)
        self.material_index[name] = len(self.gltf["materials"])
        self.gltf["materials"].append(m)
        return self.material_index[name]

    # -- binary data ----------------------------------------------------------------------------
    def _add_view(self, data: bytes, target):
        while len(self.blob) % 4:  # every bufferView starts 4-byte aligned
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data), "target": target}
        self.blob += data
        self.gltf["bufferViews"].append(view)
        return len(self.gltf["bufferViews"]) - 1

    def _add_accessor(self, view, component_type, count, type_, **extra):
        acc = {"bufferView": view, "byteOffset": 0, "componentType": component_type,
               "count": count, "type": type_}
        acc.update(extra)
        self.gltf["accessors"].append(acc)
        return len(self.gltf["accessors"]) - 1

    def add_mesh(self, mesh: Mesh, translation=None):
        assert mesh.positions and mesh.triangles
        pos32 = [tuple(f32(c) for c in p) for p in mesh.positions]
        pos_data = b"".join(struct.pack("<3f", *p) for p in pos32)
        nrm_data = b"".join(struct.pack("<3f", *n) for n in mesh.normals)
        nverts = len(mesh.positions)
        flat = [i for t in mesh.triangles for i in t]
        assert all(0 <= i < nverts for i in flat)
        if nverts <= 65535:
            idx_type, idx_data = UNSIGNED_SHORT, struct.pack("<%dH" % len(flat), *flat)
        else:
            idx_type, idx_data = UNSIGNED_INT, struct.pack("<%dI" % len(flat), *flat)

        pv = self._add_view(pos_data, ARRAY_BUFFER)
        nv = self._add_view(nrm_data, ARRAY_BUFFER)
        iv = self._add_view(idx_data, ELEMENT_ARRAY_BUFFER)
        pa = self._add_accessor(pv, FLOAT, nverts, "VEC3",
                                min=[min(p[k] for p in pos32) for k in range(3)],
                                max=[max(p[k] for p in pos32) for k in range(3)])
        na = self._add_accessor(nv, FLOAT, nverts, "VEC3")
        ia = self._add_accessor(iv, idx_type, len(flat), "SCALAR")

        self.gltf["meshes"].append({
            "name": mesh.name,
            "primitives": [{
                "attributes": {"POSITION": pa, "NORMAL": na},
                "indices": ia,
                "material": self.material_index[mesh.material],
                "mode": TRIANGLES,
            }],
        })
        node = {"name": mesh.name, "mesh": len(self.gltf["meshes"]) - 1}
        if translation is not None:
            node["translation"] = list(translation)
        self._add_node(node)

    def add_perspective_camera(self, name, translation, yfov, aspect, znear, zfar=None, rotation=None):
        persp = {"aspectRatio": aspect, "yfov": yfov, "znear": znear}
        if zfar is not None:
            persp["zfar"] = zfar
        self.gltf["cameras"].append({"name": name, "type": "perspective", "perspective": persp})
        # Without rotation a glTF camera looks down its local -Z with +Y up, as clpt wants;
        # rotation is a unit quaternion [x, y, z, w] (see look_at_rotation()).
        node = {"name": name, "camera": len(self.gltf["cameras"]) - 1,
                "translation": list(translation)}
        if rotation is not None:
            node["rotation"] = list(rotation)
        self._add_node(node)

    def _add_node(self, node):
        self.gltf["nodes"].append(node)
        self.gltf["scenes"][0]["nodes"].append(len(self.gltf["nodes"]) - 1)

    def finish(self) -> dict:
        while len(self.blob) % 4:
            self.blob.append(0)
        self.gltf["buffers"] = [{
            "byteLength": len(self.blob),
            "uri": DATA_URI_PREFIX + base64.b64encode(bytes(self.blob)).decode("ascii"),
        }]
        return self.gltf


def write_gltf(gltf: dict, path: str):
    text = json.dumps(gltf, indent=2) + "\n"
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)


# ---------------------------------------------------------------------------------------------
# validation: re-read a written file and check its structure

def read_accessor(gltf, blob, index):
    acc = gltf["accessors"][index]
    view = gltf["bufferViews"][acc["bufferView"]]
    ncomp = TYPE_COUNT[acc["type"]]
    csize = COMPONENT_SIZE[acc["componentType"]]
    elem = ncomp * csize
    stride = view.get("byteStride", elem)
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    fmt = {FLOAT: "f", UNSIGNED_SHORT: "H", UNSIGNED_INT: "I"}[acc["componentType"]]
    out = []
    for i in range(acc["count"]):
        vals = struct.unpack_from("<%d%s" % (ncomp, fmt), blob, start + i * stride)
        out.append(vals if ncomp > 1 else vals[0])
    return out


def validate(path: str) -> dict:
    """Structural checks of a written .gltf; returns per-file statistics. Raises AssertionError."""
    with open(path, "r", encoding="utf-8") as f:
        gltf = json.load(f)

    assert gltf["asset"]["version"] == "2.0"
    used = gltf.get("extensionsUsed", [])
    assert EMISSIVE_STRENGTH not in gltf.get("extensionsRequired", [])
    assert len(used) == len(set(used))

    # buffer
    assert len(gltf["buffers"]) == 1
    buf = gltf["buffers"][0]
    assert buf["uri"].startswith(DATA_URI_PREFIX)
    blob = base64.b64decode(buf["uri"][len(DATA_URI_PREFIX):], validate=True)
    assert len(blob) == buf["byteLength"], "buffer byteLength does not match its data"

    # bufferViews: in range, 4-byte aligned
    for i, v in enumerate(gltf["bufferViews"]):
        assert v["buffer"] == 0
        off = v.get("byteOffset", 0)
        assert off % 4 == 0, f"bufferView {i} byteOffset {off} not 4-byte aligned"
        assert v["byteLength"] > 0 and off + v["byteLength"] <= len(blob), f"bufferView {i} overruns"
        assert v.get("target") in (ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER)
    # views do not overlap
    spans = sorted((v.get("byteOffset", 0), v["byteLength"]) for v in gltf["bufferViews"])
    for (o0, l0), (o1, _) in zip(spans, spans[1:]):
        assert o0 + l0 <= o1, "bufferViews overlap"

    # accessors: fit their views, aligned to their component size
    for i, a in enumerate(gltf["accessors"]):
        v = gltf["bufferViews"][a["bufferView"]]
        csize = COMPONENT_SIZE[a["componentType"]]
        elem = TYPE_COUNT[a["type"]] * csize
        aoff = a.get("byteOffset", 0)
        assert a["count"] > 0
        assert aoff % csize == 0 and (v.get("byteOffset", 0) + aoff) % csize == 0
        assert aoff + a["count"] * elem <= v["byteLength"], f"accessor {i} overruns its bufferView"
        if a["componentType"] == FLOAT:
            vals = read_accessor(gltf, blob, i)
            assert all(math.isfinite(c) for p in vals for c in p)

    # materials: Lambertian, or (caustic scene) smooth glass
    for m in gltf["materials"]:
        pbr = m["pbrMetallicRoughness"]
        assert len(pbr["baseColorFactor"]) == 4
        assert all(0.0 <= c <= 1.0 for c in pbr["baseColorFactor"])
        ef = m.get("emissiveFactor", [0.0, 0.0, 0.0])
        assert len(ef) == 3 and all(0.0 <= c <= 1.0 for c in ef), "emissiveFactor outside [0,1]"
        ext = m.get("extensions", {})
        if TRANSMISSION in ext:
            assert TRANSMISSION in used and IOR in used and IOR in ext
            assert ext[TRANSMISSION]["transmissionFactor"] == 1.0 and ext[IOR]["ior"] >= 1.0
            assert pbr["metallicFactor"] == 0.0 and pbr["roughnessFactor"] == 0.0
            assert SPECULAR not in ext and "emissiveFactor" not in m, "glass: clear, not emissive"
            continue
        assert pbr["metallicFactor"] == 0.0 and pbr["roughnessFactor"] == 1.0
        assert ext[SPECULAR]["specularFactor"] == 0.0 and SPECULAR in used, "not Lambertian"
        if EMISSIVE_STRENGTH in ext:
            assert EMISSIVE_STRENGTH in used
            assert ext[EMISSIVE_STRENGTH]["emissiveStrength"] >= 0.0

    # meshes
    triangles = 0
    referenced = set()
    for mesh in gltf["meshes"]:
        for prim in mesh["primitives"]:
            assert prim.get("mode", TRIANGLES) == TRIANGLES
            assert 0 <= prim["material"] < len(gltf["materials"])
            pa, na, ia = prim["attributes"]["POSITION"], prim["attributes"]["NORMAL"], prim["indices"]
            referenced |= {pa, na, ia}
            pacc, nacc, iacc = (gltf["accessors"][k] for k in (pa, na, ia))
            assert pacc["type"] == "VEC3" and pacc["componentType"] == FLOAT
            assert nacc["type"] == "VEC3" and nacc["componentType"] == FLOAT
            assert iacc["type"] == "SCALAR" and iacc["componentType"] in (UNSIGNED_SHORT, UNSIGNED_INT)
            assert gltf["bufferViews"][pacc["bufferView"]]["target"] == ARRAY_BUFFER
            assert gltf["bufferViews"][iacc["bufferView"]]["target"] == ELEMENT_ARRAY_BUFFER
            assert pacc["count"] == nacc["count"]
            pos = read_accessor(gltf, blob, pa)
            nrm = read_accessor(gltf, blob, na)
            idx = read_accessor(gltf, blob, ia)
            # POSITION min/max are required and must be exact
            for k in range(3):
                assert pacc["min"][k] == min(p[k] for p in pos), "POSITION min wrong"
                assert pacc["max"][k] == max(p[k] for p in pos), "POSITION max wrong"
            # normals unit length
            for n in nrm:
                assert abs(length(n) - 1.0) < 1e-5, "non-unit normal"
            # indices: in range, whole triangles, not degenerate, normals agree with winding
            assert len(idx) % 3 == 0
            assert all(0 <= i < len(pos) for i in idx), "index out of range"
            if iacc["componentType"] == UNSIGNED_SHORT:
                assert len(pos) <= 65535  # 65535 is the primitive-restart value
            for t in range(0, len(idx), 3):
                i0, i1, i2 = idx[t:t + 3]
                assert len({i0, i1, i2}) == 3, "degenerate triangle"
                g = cross(sub(pos[i1], pos[i0]), sub(pos[i2], pos[i0]))
                assert length(g) > 1e-12, "zero-area triangle"
                for i in (i0, i1, i2):
                    assert dot(g, nrm[i]) > 0.0, "vertex normal disagrees with winding"
            triangles += len(idx) // 3
    assert referenced == set(range(len(gltf["accessors"]))), "unreferenced accessor"

    # nodes / scene / camera
    cams = 0
    for node in gltf["nodes"]:
        if "mesh" in node:
            assert 0 <= node["mesh"] < len(gltf["meshes"])
        if "camera" in node:
            cam = gltf["cameras"][node["camera"]]
            assert cam["type"] == "perspective"
            p = cam["perspective"]
            assert 0.0 < p["yfov"] < math.pi and p["znear"] > 0.0 and p["aspectRatio"] > 0.0
            if "rotation" in node:
                assert abs(math.sqrt(sum(c * c for c in node["rotation"])) - 1.0) < 1e-9
            cams += 1
    assert cams >= 1, "no camera node"
    roots = gltf["scenes"][gltf["scene"]]["nodes"]
    assert sorted(roots) == list(range(len(gltf["nodes"])))
    return {"gltf": gltf, "blob": blob, "triangles": triangles}


# ---------------------------------------------------------------------------------------------
# Cornell box

# The "Cornell Box Data" published by the Cornell University Program of Computer Graphics
# (https://www.graphics.cornell.edu/online/box/data.html), in millimetres, in Cornell's own
# right-handed frame: +Y up, camera at (278, 273, -800) looking down +Z, so +X is the viewer's
# LEFT (the red wall is at x ~ 556, the green one at x = 0). Each quad as published.
CORNELL_MM = {
    "floor": [[(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]],
    "ceiling": [[(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]],
    "back_wall": [[(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]],
    "right_wall_green": [[(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]],
    "left_wall_red": [[(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]],
    "short_block": [
        [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
        [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
        [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
        [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
        [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
    ],
    "tall_block": [
        [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
        [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
        [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
        [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
        [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
    ],
    # Published at y = 548.8, coplanar with the ceiling; lowered 0.1 mm (as e.g. Mitsuba's
    # version of the scene does) so the light and the ceiling do not overlap.
    "light": [[(343.0, 548.7, 227.0), (343.0, 548.7, 332.0), (213.0, 548.7, 332.0), (213.0, 548.7, 227.0)]],
}
CORNELL_CAMERA_MM = (278.0, 273.0, -800.0)
CORNELL_FOCAL_MM = 35.0
CORNELL_FILM_MM = 25.0  # square film: 25 mm x 25 mm

CORNELL_MATERIALS = {
    # name: (diffuse albedo, emitted radiance, doubleSided)
    "white": ((0.725, 0.71, 0.68), (0.0, 0.0, 0.0), True),
    "red": ((0.63, 0.065, 0.05), (0.0, 0.0, 0.0), True),
    "green": ((0.14, 0.45, 0.091), (0.0, 0.0, 0.0), True),
    "light": ((0.78, 0.78, 0.78), (17.0, 12.0, 4.0), False),
}
CORNELL_OBJECT_MATERIAL = {
    "floor": "white", "ceiling": "white", "back_wall": "white",
    "right_wall_green": "green", "left_wall_red": "red",
    "short_block": "white", "tall_block": "white", "light": "light",
}


def cornell_to_gltf(p_mm):
    """Cornell's frame (mm) -> clpt's glTF frame (m).

    Cornell's camera looks down +Z; clpt's must look down -Z. A 180 degree rotation about the
    vertical line through the camera (x = 278 mm, z = 0) does that: x' = 556 - x, z' = -z. It is
    a proper rotation, so handedness, the winding of every face and the picture are kept (red
    wall on the left, green on the right, as in Cornell's photograph), the camera stays at
    x = 0.278 m and the box stays in x in [0, 0.556] m. Mirroring z alone would also turn the
    camera round, but would mirror the picture (red wall on the right).
    """
    x, y, z = p_mm
    return ((556.0 - x) / 1000.0, y / 1000.0, -z / 1000.0 + 0.0)  # + 0.0: no -0.0


# The light of cornell_ceiling.gltf: the same quad 48.7 mm below the ceiling, emitting upward
# only, so that every path to the camera bounces off the ceiling first (the irradiance
# cache's benchmark, and the case of a light facing away from what it lights).
CORNELL_CEILING_LIGHT_Y_MM = 500.0


def make_cornell(out_dir, ceiling_light=False):
    """The Cornell box; with ceiling_light, cornell_ceiling.gltf: its light turned to face the
    ceiling from CORNELL_CEILING_LIGHT_Y_MM."""
    doc = Document("clpt scripts/make_scenes.py (Cornell Box Data, Cornell University PCG)")
    for name, (albedo, emission, ds) in CORNELL_MATERIALS.items():
        doc.add_material(name, albedo, emission, ds)

    # Orientation targets in the output frame: walls face the box's interior, blocks face out.
    interior = cornell_to_gltf((278.0, 274.4, 279.6))

    stats = {}
    for obj, quads in CORNELL_MM.items():
        mesh = Mesh(obj, CORNELL_OBJECT_MATERIAL[obj])
        if obj == "light" and ceiling_light:
            quads = [[(x, CORNELL_CEILING_LIGHT_Y_MM, z) for (x, _, z) in q] for q in quads]
        quads_m = [[cornell_to_gltf(p) for p in q] for q in quads]
        if obj.endswith("block"):
            corners = [p for q in quads_m for p in q]
            centre = scale(tuple(map(sum, zip(*corners))), 1.0 / len(corners))
        for q in quads_m:
            qc = scale(add(add(q[0], q[1]), add(q[2], q[3])), 0.25)
            # Newell normal of the quad as published (winding as given)
            n = (0.0, 0.0, 0.0)
            for i in range(4):
                n = add(n, cross(q[i], q[(i + 1) % 4]))
            if obj == "light":
                want = (0.0, 1.0 if ceiling_light else -1.0, 0.0)  # emits on one side only
            elif obj.endswith("block"):
                want = sub(qc, centre)                # outward
            else:
                want = sub(interior, qc)              # towards the interior
            if dot(n, want) < 0.0:
                q = q[::-1]                           # reverse winding: front side as wanted
            # Two triangles, each with its own flat normal: the measured walls are not all
            # planar (one red-wall corner is ~3 mm off the plane of the other three), so no shared normal.
            mesh.add_flat_triangle(q[0], q[1], q[2])
            mesh.add_flat_triangle(q[0], q[2], q[3])
            for t in mesh.triangles[-2:]:
                g = tri_normal(*(mesh.positions[i] for i in t))
                assert dot(g, want) > 0.0, f"{obj}: triangle faces the wrong way"
                if obj == "light":
                    assert (g[1] > 0.999999) if ceiling_light else (g[1] < -0.999999)
        doc.add_mesh(mesh)
        stats[obj] = len(mesh.triangles)

    yfov = 2.0 * math.atan(0.5 * CORNELL_FILM_MM / CORNELL_FOCAL_MM)
    cam = cornell_to_gltf(CORNELL_CAMERA_MM)
    doc.add_perspective_camera("cornell_camera", [round(c, 9) for c in cam], yfov, 1.0, 0.01)
    assert [round(c, 9) for c in cam] == [0.278, 0.273, 0.8]

    path = os.path.join(out_dir, "cornell_ceiling.gltf" if ceiling_light else "cornell_box.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)

    # light: area and emitted power, from what was written
    gltf, blob = res["gltf"], res["blob"]
    light_mesh = next(m for m in gltf["meshes"] if m["name"] == "light")
    prim = light_mesh["primitives"][0]
    pos = read_accessor(gltf, blob, prim["attributes"]["POSITION"])
    idx = read_accessor(gltf, blob, prim["indices"])
    area = sum(0.5 * length(cross(sub(pos[idx[t + 1]], pos[idx[t]]), sub(pos[idx[t + 2]], pos[idx[t]])))
               for t in range(0, len(idx), 3))
    mat = gltf["materials"][prim["material"]]
    radiance = [c * mat["extensions"][EMISSIVE_STRENGTH]["emissiveStrength"] for c in mat["emissiveFactor"]]
    power = [math.pi * area * L for L in radiance]
    assert abs(area - 0.130 * 0.105) < 1e-6
    assert mat["doubleSided"] is False
    # the camera is in front of the box's opening (z = 0), inside its x/y extent
    assert 0.0 < cam[0] < 0.556 and 0.0 < cam[1] < 0.5488 and cam[2] > 0.0
    print(f"{path}: {res['triangles']} triangles "
          f"({', '.join(f'{k} {v}' for k, v in stats.items())})")
    print(f"  camera (0.278, 0.273, 0.8) looking down -Z, yfov {math.degrees(yfov):.4f} deg "
          f"({yfov:.6f} rad), aspect 1")
    print(f"  light area {area:.6f} m^2, radiance ({radiance[0]:g}, {radiance[1]:g}, {radiance[2]:g}) "
          f"W/m^2/sr, power pi*A*L = ({power[0]:.4f}, {power[1]:.4f}, {power[2]:.4f}) W")
    return res


# ---------------------------------------------------------------------------------------------
# Furnace

def icosphere(subdivisions):
    """Unit icosahedron subdivided `subdivisions` times, projected onto the unit sphere.
    Returns (vertices, triangles) with counter-clockwise, outward-facing triangles."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [normalize(v) for v in [
        (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
        (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
        (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
        (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
        (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
        (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                verts.append(normalize(scale(add(verts[a], verts[b]), 0.5)))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    for a, b, c in faces:  # outward and counter-clockwise
        assert dot(cross(sub(verts[b], verts[a]), sub(verts[c], verts[a])), verts[a]) > 0.0
    return verts, faces


FURNACE_ALBEDO = 0.5
FURNACE_RADIANCE = 1.0
FURNACE_SUBDIVISIONS = 3  # 20 * 4^3 = 1280 triangles per sphere


def sphere_mesh(name, material, radius, inward, subdivisions):
    # Flat facets (face normals): smooth shading normals on a polyhedron do not conserve
    # energy exactly, and the furnace's closed-form answer relies on every surface being an
    # exact Lambertian reflector.
    unit, faces = icosphere(subdivisions)
    mesh = Mesh(name, material)
    for a, b, c in faces:
        corners = [scale(unit[i], radius) for i in ((a, c, b) if inward else (a, b, c))]
        mesh.add_flat_triangle(*corners)
    return mesh


def furnace_expected(depth, albedo=FURNACE_ALBEDO, le=FURNACE_RADIANCE):
    """L for maximum path depth `depth` (number of bounces; 0 = emission only); None = infinity."""
    if depth is None:
        return le / (1.0 - albedo)
    return le * (1.0 - albedo ** (depth + 1)) / (1.0 - albedo)


def make_furnace(out_dir):
    doc = Document("clpt scripts/make_scenes.py (furnace test)")
    rho, le = FURNACE_ALBEDO, FURNACE_RADIANCE
    doc.add_material("furnace", (rho, rho, rho), (le, le, le), double_sided=True)
    enclosure = sphere_mesh("enclosure", "furnace", 5.0, True, FURNACE_SUBDIVISIONS)
    inner = sphere_mesh("inner_sphere", "furnace", 1.0, False, FURNACE_SUBDIVISIONS)
    for mesh, inward in ((enclosure, True), (inner, False)):
        for t in mesh.triangles:
            p0, p1, p2 = (mesh.positions[i] for i in t)
            g = tri_normal(p0, p1, p2)
            c = scale(add(add(p0, p1), p2), 1.0 / 3.0)
            assert (dot(g, c) < 0.0) == inward, f"{mesh.name}: triangle faces the wrong way"
        doc.add_mesh(mesh)
    doc.add_perspective_camera("furnace_camera", [0.0, 0.0, 3.5], math.radians(45.0), 1.0, 0.01)

    path = os.path.join(out_dir, "furnace.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)

    # every surface point has the same material: a single shared one
    gltf = res["gltf"]
    assert len(gltf["materials"]) == 1
    m = gltf["materials"][0]
    assert m["emissiveFactor"] == [1.0, 1.0, 1.0]
    assert m["extensions"][EMISSIVE_STRENGTH]["emissiveStrength"] == le
    # the camera is inside the enclosure polyhedron (closer to the origin than any of its
    # face planes) and outside the inner sphere (whose vertices lie at radius 1)
    closest_face = min(abs(dot(tri_normal(*(enclosure.positions[i] for i in t)), enclosure.positions[t[0]]))
                       for t in enclosure.triangles)
    assert 1.0 < 3.5 < closest_face, closest_face
    print(f"{path}: {res['triangles']} triangles (enclosure {len(enclosure.triangles)}, "
          f"inner_sphere {len(inner.triangles)}), {len(enclosure.positions) + len(inner.positions)} vertices")
    table = ", ".join(f"D={d if d is not None else 'inf'}: {furnace_expected(d):g}"
                      for d in (0, 1, 2, 4, 8, None))
    print(f"  albedo {rho}, Le {le}: expected L = Le(1-rho^(D+1))/(1-rho): {table}")
    return res


# ---------------------------------------------------------------------------------------------
# Helpers for the benchmark scenes: camera orientation, quads, UV sphere

def look_at_rotation(eye, target):
    """Unit quaternion [x, y, z, w] turning a glTF camera (looking down -Z, +Y up) to look from
    eye at target with no roll: yaw about +Y, then pitch about the camera's +X."""
    d = normalize(sub(target, eye))
    yaw = math.atan2(-d[0], -d[2])
    pitch = math.asin(max(-1.0, min(1.0, d[1])))
    sy, cy = math.sin(0.5 * yaw), math.cos(0.5 * yaw)
    sx, cx = math.sin(0.5 * pitch), math.cos(0.5 * pitch)
    q = [cy * sx, sy * cx, -sy * sx, cy * cx]  # q_yaw * q_pitch
    assert length(sub(quat_rotate(q, (0.0, 0.0, -1.0)), d)) < 1e-9
    assert abs(quat_rotate(q, (1.0, 0.0, 0.0))[1]) < 1e-9  # no roll: the image's x stays level
    return [round(c, 9) for c in q]


def quat_rotate(q, v):
    """v rotated by the unit quaternion q = [x, y, z, w]."""
    u, w = (q[0], q[1], q[2]), q[3]
    t = scale(cross(u, v), 2.0)
    return add(add(v, scale(t, w)), cross(u, t))


def add_quad(mesh, corners, want):
    """Planar quad as two flat triangles whose front side faces `want` (winding reversed when
    the corners as given face the other way)."""
    q = list(corners)
    if dot(cross(sub(q[1], q[0]), sub(q[2], q[0])), want) < 0.0:
        q = q[::-1]
    mesh.add_flat_triangle(q[0], q[1], q[2])
    mesh.add_flat_triangle(q[0], q[2], q[3])
    for t in mesh.triangles[-2:]:
        assert dot(tri_normal(*(mesh.positions[i] for i in t)), want) > 0.0, f"{mesh.name}: wrong way"


def add_horizontal_square(mesh, centre, size, facing):
    """A size x size square in the plane y = centre's y, its front side up (facing +1) or down
    (facing -1): the scenes' small area lights."""
    cx, y, cz = centre
    h = 0.5 * size
    add_quad(mesh, [(cx - h, y, cz - h), (cx + h, y, cz - h), (cx + h, y, cz + h), (cx - h, y, cz + h)],
             (0.0, float(facing), 0.0))


def add_box(mesh, lo, hi, outward=True, skip=()):
    """Axis-aligned box [lo, hi] as quads facing out (or in); faces named in skip ('+x', '-x',
    '+y', '-y', '+z', '-z') are left open."""
    centre = scale(add(lo, hi), 0.5)
    for axis in range(3):
        for sign in (-1.0, 1.0):
            face = ("-" if sign < 0.0 else "+") + "xyz"[axis]
            if face in skip:
                continue
            v = hi[axis] if sign > 0.0 else lo[axis]
            a, b = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for ua, ub in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = v
                p[a] = hi[a] if ua else lo[a]
                p[b] = hi[b] if ub else lo[b]
                corners.append(tuple(p))
            n = [0.0, 0.0, 0.0]
            n[axis] = sign if outward else -sign
            add_quad(mesh, corners, tuple(n))
    return centre


def uv_sphere(mesh, centre, radius, segments, rings):
    """UV sphere with shared vertices and smooth normals (the exact sphere normal at each
    vertex): `segments` around +Y, `rings` from pole to pole, 2 * segments * (rings - 1)
    counter-clockwise, outward triangles."""
    top = mesh.add_vertex(add(centre, (0.0, radius, 0.0)), (0.0, 1.0, 0.0))
    rows = []
    for r in range(1, rings):
        theta = math.pi * r / rings
        row = []
        for k in range(segments):
            phi = 2.0 * math.pi * k / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            row.append(mesh.add_vertex(add(centre, scale(n, radius)), n))
        rows.append(row)
    bottom = mesh.add_vertex(add(centre, (0.0, -radius, 0.0)), (0.0, -1.0, 0.0))
    first = len(mesh.triangles)
    for k in range(segments):
        k1 = (k + 1) % segments
        mesh.triangles.append((top, rows[0][k], rows[0][k1]))
        for r in range(rings - 2):
            a, b, c, d = rows[r][k], rows[r + 1][k], rows[r + 1][k1], rows[r][k1]
            mesh.triangles.append((a, b, c))
            mesh.triangles.append((a, c, d))
        mesh.triangles.append((bottom, rows[-1][k1], rows[-1][k]))
    for t in mesh.triangles[first:]:  # outward and counter-clockwise
        p0, p1, p2 = (mesh.positions[i] for i in t)
        g = cross(sub(p1, p0), sub(p2, p0))
        assert dot(g, sub(scale(add(add(p0, p1), p2), 1.0 / 3.0), centre)) > 0.0
    return len(mesh.triangles) - first


def emitter_summary(res, mesh_name):
    """(area, radiance, power, front normal) of the emissive mesh `mesh_name`, from the file."""
    gltf, blob = res["gltf"], res["blob"]
    prim = next(m for m in gltf["meshes"] if m["name"] == mesh_name)["primitives"][0]
    pos = read_accessor(gltf, blob, prim["attributes"]["POSITION"])
    idx = read_accessor(gltf, blob, prim["indices"])
    tris = [(pos[idx[t]], pos[idx[t + 1]], pos[idx[t + 2]]) for t in range(0, len(idx), 3)]
    area = sum(0.5 * length(cross(sub(b, a), sub(c, a))) for a, b, c in tris)
    mat = gltf["materials"][prim["material"]]
    radiance = [c * mat["extensions"][EMISSIVE_STRENGTH]["emissiveStrength"] for c in mat["emissiveFactor"]]
    power = [math.pi * area * L for L in radiance]
    normals = {tuple(round(c, 6) for c in tri_normal(a, b, c)) for a, b, c in tris}
    assert len(normals) == 1 and mat["doubleSided"] is False
    return area, radiance, power, normals.pop()


# ---------------------------------------------------------------------------------------------
# Caustic benchmark: a glass sphere on a diffuse floor under a small light

CAUSTIC_FLOOR_HALF = 5.0               # floor: 10 m x 10 m at y = 0, centred on the origin
CAUSTIC_FLOOR_ALBEDO = 0.6
CAUSTIC_SPHERE_CENTRE = (0.0, 0.5, 0.0)
CAUSTIC_SPHERE_RADIUS = 0.5            # resting on the floor
CAUSTIC_SPHERE_SEGMENTS, CAUSTIC_SPHERE_RINGS = 64, 32   # 2 * 64 * 31 = 3968 triangles
CAUSTIC_GLASS_IOR = 1.5
CAUSTIC_LIGHT_CENTRE = (-2.7, 2.4, 0.0)
CAUSTIC_LIGHT_SIZE = 0.05              # square, facing down
CAUSTIC_LIGHT_RADIANCE = 25600.0
CAUSTIC_CAMERA = (0.9, 1.7, 2.6)
CAUSTIC_TARGET = (0.4, 0.3, 0.0)
CAUSTIC_YFOV_DEG = 40.0


def make_caustic(out_dir):
    doc = Document("clpt scripts/make_scenes.py (caustic benchmark)")
    a = CAUSTIC_FLOOR_ALBEDO
    doc.add_material("floor", (a, a, a))
    doc.add_glass_material("glass", CAUSTIC_GLASS_IOR)
    doc.add_material("light", (0.78, 0.78, 0.78), (CAUSTIC_LIGHT_RADIANCE,) * 3, double_sided=False)

    h = CAUSTIC_FLOOR_HALF
    floor = Mesh("floor", "floor")
    add_quad(floor, [(-h, 0.0, -h), (h, 0.0, -h), (h, 0.0, h), (-h, 0.0, h)], (0.0, 1.0, 0.0))
    doc.add_mesh(floor)

    sphere = Mesh("glass_sphere", "glass")
    uv_sphere(sphere, CAUSTIC_SPHERE_CENTRE, CAUSTIC_SPHERE_RADIUS,
              CAUSTIC_SPHERE_SEGMENTS, CAUSTIC_SPHERE_RINGS)
    doc.add_mesh(sphere)

    light = Mesh("light", "light")
    add_horizontal_square(light, CAUSTIC_LIGHT_CENTRE, CAUSTIC_LIGHT_SIZE, -1)  # emits downward only
    doc.add_mesh(light)

    yfov = math.radians(CAUSTIC_YFOV_DEG)
    doc.add_perspective_camera("caustic_camera", list(CAUSTIC_CAMERA), yfov, 1.0, 0.01,
                               rotation=look_at_rotation(CAUSTIC_CAMERA, CAUSTIC_TARGET))

    path = os.path.join(out_dir, "caustic.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)

    area, radiance, power, normal = emitter_summary(res, "light")
    assert abs(area - CAUSTIC_LIGHT_SIZE ** 2) < 1e-7 and normal == (0.0, -1.0, 0.0)
    # the sphere rests on the floor, the light is above it, the camera above the floor
    assert abs(CAUSTIC_SPHERE_CENTRE[1] - CAUSTIC_SPHERE_RADIUS) < 1e-12
    assert CAUSTIC_LIGHT_CENTRE[1] > 2.0 * CAUSTIC_SPHERE_RADIUS and CAUSTIC_CAMERA[1] > 0.0
    # paraxial ball lens: focal length n R / (2 (n - 1)) from the centre; image of the light
    n, r = CAUSTIC_GLASS_IOR, CAUSTIC_SPHERE_RADIUS
    f = n * r / (2.0 * (n - 1.0))
    to_centre = sub(CAUSTIC_SPHERE_CENTRE, CAUSTIC_LIGHT_CENTRE)
    u = length(to_centre)
    v = 1.0 / (1.0 / f - 1.0 / u)
    d = normalize(to_centre)
    t_floor = CAUSTIC_SPHERE_CENTRE[1] / -d[1]
    hit = add(CAUSTIC_SPHERE_CENTRE, scale(d, t_floor))
    print(f"{path}: {res['triangles']} triangles (floor {len(floor.triangles)}, glass_sphere "
          f"{len(sphere.triangles)} ({CAUSTIC_SPHERE_SEGMENTS}x{CAUSTIC_SPHERE_RINGS} UV sphere, smooth "
          f"normals), light {len(light.triangles)})")
    print(f"  camera {CAUSTIC_CAMERA} looking at {CAUSTIC_TARGET}, yfov {CAUSTIC_YFOV_DEG:g} deg, aspect 1")
    print(f"  light {CAUSTIC_LIGHT_SIZE} m square at {CAUSTIC_LIGHT_CENTRE} facing down, radiance "
          f"{radiance[0]:g} W/m^2/sr, power pi*A*L = {power[0]:.2f} W")
    print(f"  glass sphere r {r} ior {n}: paraxial focus {v:.3f} m behind its centre, floor "
          f"{t_floor:.3f} m; caustic centre near ({hit[0]:.2f}, 0, {hit[2]:.2f})")
    return res


# ---------------------------------------------------------------------------------------------
# Indirect benchmark: a closed room lit by a lamp shining at the ceiling

ROOM_LO, ROOM_HI = (-2.0, 0.0, -2.5), (2.0, 2.6, 2.5)   # 4 m x 2.6 m x 5 m, inside
ROOM_ALBEDO = 0.7
ROOM_BLOCK = ((0.3, 0.0, -1.6), (1.3, 0.8, -0.6))        # a 1 m x 0.8 m x 1 m block on the floor
SHADE_LO, SHADE_HI = (-0.95, 1.75, -1.45), (-0.55, 2.0, -1.05)  # open-topped lamp shade
SHADE_ALBEDO = 0.5
LAMP_SIZE = 0.3                                          # square, facing up, inside the shade
LAMP_HEIGHT = 1.77
LAMP_RADIANCE = 150.0
ROOM_CAMERA = (0.0, 1.4, 2.3)
ROOM_TARGET = (-0.2, 1.2, -2.5)
ROOM_YFOV_DEG = 60.0


def make_indirect(out_dir):
    doc = Document("clpt scripts/make_scenes.py (indirect benchmark)")
    a = ROOM_ALBEDO
    doc.add_material("wall", (a, a, a))
    b = SHADE_ALBEDO
    doc.add_material("shade", (b, b, b))
    doc.add_material("lamp", (0.78, 0.78, 0.78), (LAMP_RADIANCE,) * 3, double_sided=False)

    room = Mesh("room", "wall")   # floor, ceiling and four walls, facing the inside
    add_box(room, ROOM_LO, ROOM_HI, outward=False)
    doc.add_mesh(room)
    block = Mesh("block", "wall")
    add_box(block, *ROOM_BLOCK, outward=True, skip=("-y",))
    doc.add_mesh(block)
    shade = Mesh("lamp_shade", "shade")  # four sides and a bottom, open at the top
    add_box(shade, SHADE_LO, SHADE_HI, outward=True, skip=("+y",))
    doc.add_mesh(shade)

    lamp = Mesh("lamp", "lamp")
    cx, cz = 0.5 * (SHADE_LO[0] + SHADE_HI[0]), 0.5 * (SHADE_LO[2] + SHADE_HI[2])
    s, y = 0.5 * LAMP_SIZE, LAMP_HEIGHT
    add_horizontal_square(lamp, (cx, y, cz), LAMP_SIZE, 1)  # emits upward only
    doc.add_mesh(lamp)

    yfov = math.radians(ROOM_YFOV_DEG)
    doc.add_perspective_camera("room_camera", list(ROOM_CAMERA), yfov, 1.0, 0.01,
                               rotation=look_at_rotation(ROOM_CAMERA, ROOM_TARGET))

    path = os.path.join(out_dir, "indirect.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)

    area, radiance, power, normal = emitter_summary(res, "lamp")
    assert abs(area - LAMP_SIZE ** 2) < 1e-7 and normal == (0.0, 1.0, 0.0)
    # the lamp lies inside the shade, below its rim and above its bottom; everything inside the room
    assert SHADE_LO[1] < LAMP_HEIGHT < SHADE_HI[1]
    assert SHADE_LO[0] < cx - s and cx + s < SHADE_HI[0] and SHADE_LO[2] < cz - s and cz + s < SHADE_HI[2]
    for p in (SHADE_LO, SHADE_HI, *ROOM_BLOCK, ROOM_CAMERA):
        assert all(ROOM_LO[k] <= p[k] <= ROOM_HI[k] for k in range(3))
    assert all(ROOM_LO[k] < ROOM_CAMERA[k] < ROOM_HI[k] for k in range(3))
    print(f"{path}: {res['triangles']} triangles (room {len(room.triangles)}, block {len(block.triangles)}, "
          f"lamp_shade {len(shade.triangles)}, lamp {len(lamp.triangles)})")
    print(f"  camera {ROOM_CAMERA} looking at {ROOM_TARGET}, yfov {ROOM_YFOV_DEG:g} deg, aspect 1")
    print(f"  lamp {LAMP_SIZE} m square at ({cx:g}, {y:g}, {cz:g}) facing up (the ceiling) inside an "
          f"open-topped shade, radiance {radiance[0]:g} W/m^2/sr, power pi*A*L = {power[0]:.2f} W")
    return res


# ---------------------------------------------------------------------------------------------
# Glass-room benchmark (vcm, issue 18): the indirect room's walls and block with a glass
# sphere on the block and a small light above it, so that one image has diffuse
# inter-reflection (bdpt's strength), a caustic on the block (light tracing's) and that caustic
# seen through the sphere (E S S D S S L: merging's alone)

GLASS_ROOM_SPHERE_CENTRE = (0.8, 1.15, -1.1)   # resting on the block's top (y = 0.8)
GLASS_ROOM_SPHERE_RADIUS = 0.35
GLASS_ROOM_LIGHT_CENTRE = (0.3, 2.5, -0.6)     # 0.1 m under the ceiling, up and to the side
GLASS_ROOM_LIGHT_SIZE = 0.1                    # square, facing down
GLASS_ROOM_LIGHT_RADIANCE = 1000.0
GLASS_ROOM_CAMERA = (-0.6, 1.6, 2.2)
GLASS_ROOM_TARGET = (0.6, 0.9, -1.1)
GLASS_ROOM_YFOV_DEG = 50.0


def make_glass_room(out_dir):
    doc = Document("clpt scripts/make_scenes.py (glass room benchmark)")
    a = ROOM_ALBEDO
    doc.add_material("wall", (a, a, a))
    doc.add_glass_material("glass", CAUSTIC_GLASS_IOR)
    doc.add_material("light", (0.78, 0.78, 0.78), (GLASS_ROOM_LIGHT_RADIANCE,) * 3, double_sided=False)

    room = Mesh("room", "wall")
    add_box(room, ROOM_LO, ROOM_HI, outward=False)
    doc.add_mesh(room)
    block = Mesh("block", "wall")
    add_box(block, *ROOM_BLOCK, outward=True, skip=("-y",))
    doc.add_mesh(block)
    sphere = Mesh("glass_sphere", "glass")
    uv_sphere(sphere, GLASS_ROOM_SPHERE_CENTRE, GLASS_ROOM_SPHERE_RADIUS,
              CAUSTIC_SPHERE_SEGMENTS, CAUSTIC_SPHERE_RINGS)
    doc.add_mesh(sphere)
    light = Mesh("light", "light")
    add_horizontal_square(light, GLASS_ROOM_LIGHT_CENTRE, GLASS_ROOM_LIGHT_SIZE, -1)  # emits downward only
    doc.add_mesh(light)

    doc.add_perspective_camera("glass_room_camera", list(GLASS_ROOM_CAMERA),
                               math.radians(GLASS_ROOM_YFOV_DEG), 1.0, 0.01,
                               rotation=look_at_rotation(GLASS_ROOM_CAMERA, GLASS_ROOM_TARGET))
    path = os.path.join(out_dir, "glass_room.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)
    area, radiance, power, normal = emitter_summary(res, "light")
    assert abs(area - GLASS_ROOM_LIGHT_SIZE ** 2) < 1e-7 and normal == (0.0, -1.0, 0.0)
    # the sphere rests on the block, inside its top face; light and camera inside the room
    assert abs(GLASS_ROOM_SPHERE_CENTRE[1] - GLASS_ROOM_SPHERE_RADIUS - ROOM_BLOCK[1][1]) < 1e-12
    for k in (0, 2):
        assert ROOM_BLOCK[0][k] < GLASS_ROOM_SPHERE_CENTRE[k] - GLASS_ROOM_SPHERE_RADIUS
        assert GLASS_ROOM_SPHERE_CENTRE[k] + GLASS_ROOM_SPHERE_RADIUS < ROOM_BLOCK[1][k]
    for p in (GLASS_ROOM_LIGHT_CENTRE, GLASS_ROOM_CAMERA):
        assert all(ROOM_LO[k] < p[k] < ROOM_HI[k] for k in range(3))
    print(f"{path}: {res['triangles']} triangles (room {len(room.triangles)}, block {len(block.triangles)}, "
          f"glass_sphere {len(sphere.triangles)}, light {len(light.triangles)})")
    print(f"  light {GLASS_ROOM_LIGHT_SIZE} m square at {GLASS_ROOM_LIGHT_CENTRE} facing down, radiance "
          f"{radiance[0]:g} W/m^2/sr, power {power[0]:.2f} W; glass sphere r {GLASS_ROOM_SPHERE_RADIUS} "
          f"on the block")
    return res


# ---------------------------------------------------------------------------------------------
# Glass-table benchmark (vcm, issue 18): the indirect room's walls with a glass-topped table
# under a small lamp. The floor under the table is lit through the glass and seen through it
# from above (E S S D S S L: merging's alone, a large share of the image), the rest of the
# room by the lamp and by inter-reflection (connections' strength)

GLASS_TABLE_TOP_LO, GLASS_TABLE_TOP_HI = (-0.7, 0.72, -1.5), (0.7, 0.76, -0.5)  # a 4 cm glass slab
GLASS_TABLE_LEG = 0.05                         # square legs of the wall's material, inset by a leg
GLASS_TABLE_LIGHT_CENTRE = (0.0, 2.55, -1.0)   # 5 cm under the ceiling, over the table
GLASS_TABLE_LIGHT_SIZE = 0.1                   # square, facing down
GLASS_TABLE_LIGHT_RADIANCE = 1000.0
GLASS_TABLE_CAMERA = (0.4, 2.0, 0.0)
GLASS_TABLE_TARGET = (0.0, 0.2, -1.0)
GLASS_TABLE_YFOV_DEG = 50.0


def make_glass_table(out_dir):
    doc = Document("clpt scripts/make_scenes.py (glass table benchmark)")
    a = ROOM_ALBEDO
    doc.add_material("wall", (a, a, a))
    doc.add_glass_material("glass", CAUSTIC_GLASS_IOR)
    doc.add_material("light", (0.78, 0.78, 0.78), (GLASS_TABLE_LIGHT_RADIANCE,) * 3, double_sided=False)

    room = Mesh("room", "wall")
    add_box(room, ROOM_LO, ROOM_HI, outward=False)
    doc.add_mesh(room)
    top = Mesh("table_top", "glass")
    add_box(top, GLASS_TABLE_TOP_LO, GLASS_TABLE_TOP_HI, outward=True)
    doc.add_mesh(top)
    legs = Mesh("table_legs", "wall")
    (x0, y0, z0), (x1, _, z1) = GLASS_TABLE_TOP_LO, GLASS_TABLE_TOP_HI
    w = GLASS_TABLE_LEG
    for lx in (x0 + w, x1 - 2.0 * w):
        for lz in (z0 + w, z1 - 2.0 * w):
            add_box(legs, (lx, 0.0, lz), (lx + w, y0, lz + w), outward=True, skip=("-y", "+y"))
    doc.add_mesh(legs)
    light = Mesh("light", "light")
    add_horizontal_square(light, GLASS_TABLE_LIGHT_CENTRE, GLASS_TABLE_LIGHT_SIZE, -1)  # emits downward only
    doc.add_mesh(light)

    doc.add_perspective_camera("glass_table_camera", list(GLASS_TABLE_CAMERA),
                               math.radians(GLASS_TABLE_YFOV_DEG), 1.0, 0.01,
                               rotation=look_at_rotation(GLASS_TABLE_CAMERA, GLASS_TABLE_TARGET))
    path = os.path.join(out_dir, "glass_table.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)
    area, radiance, power, normal = emitter_summary(res, "light")
    assert abs(area - GLASS_TABLE_LIGHT_SIZE ** 2) < 1e-7 and normal == (0.0, -1.0, 0.0)
    # the lamp is over the table top, so that its direct light onto the floor under the table
    # passes through the glass; light, table and camera inside the room
    cx, cy, cz = GLASS_TABLE_LIGHT_CENTRE
    assert x0 < cx < x1 and z0 < cz < z1 and cy > GLASS_TABLE_TOP_HI[1]
    for p in (GLASS_TABLE_TOP_LO, GLASS_TABLE_TOP_HI, GLASS_TABLE_LIGHT_CENTRE, GLASS_TABLE_CAMERA):
        assert all(ROOM_LO[k] < p[k] < ROOM_HI[k] for k in range(3))
    print(f"{path}: {res['triangles']} triangles (room {len(room.triangles)}, table_top {len(top.triangles)}, "
          f"table_legs {len(legs.triangles)}, light {len(light.triangles)})")
    print(f"  light {GLASS_TABLE_LIGHT_SIZE} m square at {GLASS_TABLE_LIGHT_CENTRE} facing down, radiance "
          f"{radiance[0]:g} W/m^2/sr, power {power[0]:.2f} W; glass top {GLASS_TABLE_TOP_LO} to "
          f"{GLASS_TABLE_TOP_HI}")
    return res


# ---------------------------------------------------------------------------------------------
# Door-ajar benchmark: two rooms, the lamp in one, the camera in the other, light through a
# door left slightly open (Veach 1997's hard case for path tracing, built anew here)

DOOR_ROOM_LO, DOOR_ROOM_HI = (-2.0, 0.0, -3.0), (2.0, 2.5, 3.0)  # both rooms, inside
DOOR_WALL_Z = 0.05                     # the dividing wall spans z in [-0.05, 0.05]
DOOR_OPENING_X = (0.2, 1.0)            # the doorway: 0.8 m wide ...
DOOR_OPENING_TOP = 2.0                 # ... and 2 m high
DOOR_THICKNESS = 0.04
DOOR_ANGLE_DEG = 8.0                   # open by 8 degrees into the lamp's room (z < 0)
DOOR_ALBEDO = 0.6
DOOR_ROOM_ALBEDO = 0.7
DOOR_LAMP_LO, DOOR_LAMP_HI = (-0.6, -2.6), (0.6, -1.8)  # x, z of a lamp facing the ceiling
DOOR_LAMP_HEIGHT = 1.8
DOOR_LAMP_RADIANCE = 60.0
DOOR_CAMERA = (-1.6, 1.3, 2.8)
DOOR_TARGET = (0.6, 0.5, 0.0)
DOOR_YFOV_DEG = 55.0


def add_door_panel(mesh, hinge, width, y0, y1, thickness, angle):
    """A box of width x (y1 - y0) x thickness, closed along +x from `hinge` (x, z) with its
    faces between z = hinge z and hinge z - thickness, turned by `angle` about the hinge's
    vertical axis so that its free edge swings towards -z."""
    c, s_ = math.cos(angle), math.sin(angle)
    hx, hz = hinge

    def at(u, v, y):  # u along the closed door (+x), v across it (-z), turned
        return (hx + u * c - v * s_, y, hz - u * s_ - v * c)

    along, across = (c, 0.0, -s_), (-s_, 0.0, -c)
    faces = [  # (corners in (u, v), y pairs, outward normal)
        ([(0, 0, y0), (width, 0, y0), (width, 0, y1), (0, 0, y1)], scale(across, -1.0)),
        ([(0, thickness, y0), (width, thickness, y0), (width, thickness, y1), (0, thickness, y1)], across),
        ([(0, 0, y0), (0, thickness, y0), (0, thickness, y1), (0, 0, y1)], scale(along, -1.0)),
        ([(width, 0, y0), (width, thickness, y0), (width, thickness, y1), (width, 0, y1)], along),
        ([(0, 0, y0), (width, 0, y0), (width, thickness, y0), (0, thickness, y0)], (0.0, -1.0, 0.0)),
        ([(0, 0, y1), (width, 0, y1), (width, thickness, y1), (0, thickness, y1)], (0.0, 1.0, 0.0)),
    ]
    for corners, n in faces:
        add_quad(mesh, [at(u, v, y) for u, v, y in corners], n)


def make_door(out_dir):
    doc = Document("clpt scripts/make_scenes.py (door-ajar benchmark)")
    a = DOOR_ROOM_ALBEDO
    doc.add_material("wall", (a, a, a))
    d = DOOR_ALBEDO
    doc.add_material("door", (d, d, d))
    doc.add_material("lamp", (0.78, 0.78, 0.78), (DOOR_LAMP_RADIANCE,) * 3, double_sided=False)

    room = Mesh("rooms", "wall")
    add_box(room, DOOR_ROOM_LO, DOOR_ROOM_HI, outward=False)
    doc.add_mesh(room)
    (x0, y0r, _), (x1, y1r, _) = DOOR_ROOM_LO, DOOR_ROOM_HI
    ox0, ox1 = DOOR_OPENING_X
    wall = Mesh("dividing_wall", "wall")  # left of the doorway, right of it, above it
    add_box(wall, (x0, y0r, -DOOR_WALL_Z), (ox0, y1r, DOOR_WALL_Z), skip=("-x", "-y", "+y"))
    add_box(wall, (ox1, y0r, -DOOR_WALL_Z), (x1, y1r, DOOR_WALL_Z), skip=("+x", "-y", "+y"))
    add_box(wall, (ox0, DOOR_OPENING_TOP, -DOOR_WALL_Z), (ox1, y1r, DOOR_WALL_Z), skip=("-x", "+x", "+y"))
    doc.add_mesh(wall)
    door = Mesh("door", "door")  # 5 mm clear of the floor and of the lintel
    add_door_panel(door, (ox0, -DOOR_WALL_Z), ox1 - ox0 - 0.01, 0.005, DOOR_OPENING_TOP - 0.005,
                   DOOR_THICKNESS, math.radians(DOOR_ANGLE_DEG))
    doc.add_mesh(door)

    lamp = Mesh("lamp", "lamp")
    (lx0, lz0), (lx1, lz1) = DOOR_LAMP_LO, DOOR_LAMP_HI
    y = DOOR_LAMP_HEIGHT
    add_quad(lamp, [(lx0, y, lz0), (lx1, y, lz0), (lx1, y, lz1), (lx0, y, lz1)], (0.0, 1.0, 0.0))
    doc.add_mesh(lamp)

    doc.add_perspective_camera("door_camera", list(DOOR_CAMERA), math.radians(DOOR_YFOV_DEG), 1.0, 0.01,
                               rotation=look_at_rotation(DOOR_CAMERA, DOOR_TARGET))
    path = os.path.join(out_dir, "door_ajar.gltf")
    write_gltf(doc.finish(), path)
    res = validate(path)
    area, radiance, power, normal = emitter_summary(res, "lamp")
    assert normal == (0.0, 1.0, 0.0) and lz1 < -DOOR_WALL_Z and DOOR_CAMERA[2] > DOOR_WALL_Z
    print(f"{path}: {res['triangles']} triangles; lamp {area:g} m^2 facing the far room's ceiling, "
          f"radiance {radiance[0]:g} W/m^2/sr, power {power[0]:.1f} W; door open {DOOR_ANGLE_DEG:g} deg; "
          f"camera {DOOR_CAMERA} in the near room")
    return res


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(here, os.pardir, "scenes"),
                    help="output directory (default: the repository's scenes/)")
    args = ap.parse_args(argv)
    out_dir = os.path.normpath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    make_cornell(out_dir)
    make_cornell(out_dir, ceiling_light=True)
    make_furnace(out_dir)
    make_caustic(out_dir)
    make_indirect(out_dir)
    make_door(out_dir)
    make_glass_room(out_dir)
    make_glass_table(out_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
