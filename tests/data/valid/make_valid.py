#!/usr/bin/env python3
"""Writes the small valid glTF files used by tests/gltf_loader_test.cpp (python3, standard library).

Run it from anywhere; it writes next to itself. The outputs are committed, so the tests do not
need Python. The expected values in the test (world positions, winding) are worked out by hand
in README.md, not taken from this script.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def layout(chunks):
    """Concatenates byte chunks, each starting on a 4-byte boundary. Returns (data, [(offset, length)])."""
    data = b""
    spans = []
    for c in chunks:
        data += b"\0" * (-len(data) % 4)
        spans.append((len(data), len(c)))
        data += c
    data += b"\0" * (-len(data) % 4)
    return data, spans


def floats(values):
    return struct.pack("<%df" % len(values), *values)


def write_json(name, doc):
    with open(os.path.join(HERE, name), "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def glb(doc, bin_data):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    out = struct.pack("<I", len(js)) + b"JSON" + js
    if bin_data:
        out += struct.pack("<I", len(bin_data)) + b"BIN\0" + bin_data
    return b"glTF" + struct.pack("<II", 2, 12 + len(out)) + out


def quad_trs_u8():
    # A unit quad in the XY plane (normal +Z, counter-clockwise seen from +Z), u8 indices,
    # normalized u8 UVs in a strided view, under a parent with translation and uniform scale.
    pos = floats([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0])
    nrm = floats([0, 0, 1] * 4)
    uv = bytes([0, 0, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0, 0, 255, 0, 0])  # stride 4, 2 bytes used
    idx = bytes([0, 1, 2, 0, 2, 3])
    data, spans = layout([pos, nrm, uv, idx])
    with open(os.path.join(HERE, "quad_trs_u8.bin"), "wb") as f:
        f.write(data)
    s = 0.7071067811865476
    doc = {
        "asset": {"version": "2.0", "generator": "clpt tests/data/valid/make_valid.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "Parent", "translation": [10, 0, 0], "scale": [2, 2, 2], "children": [1, 2]},
            {"name": "Quad", "translation": [0, 1, 0], "rotation": [0, 0, s, s], "mesh": 0},
            {"name": "CameraNode", "translation": [0, 0, 5], "camera": 0},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{
            "name": "Lamp",
            "doubleSided": True,
            "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0],
                                     "metallicFactor": 0.25, "roughnessFactor": 0.75},
            "emissiveFactor": [1.0, 0.5, 0.0],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}},
        }],
        "buffers": [{"uri": "quad_trs_u8.bin", "byteLength": len(data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": spans[0][0], "byteLength": spans[0][1]},
            {"buffer": 0, "byteOffset": spans[1][0], "byteLength": spans[1][1]},
            {"buffer": 0, "byteOffset": spans[2][0], "byteLength": spans[2][1], "byteStride": 4},
            {"buffer": 0, "byteOffset": spans[3][0], "byteLength": spans[3][1]},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5121, "normalized": True, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5121, "count": 6, "type": "SCALAR"},
        ],
    }
    write_json("quad_trs_u8.gltf", doc)


def strip_fan():
    # Mesh 0: TRIANGLE_STRIP of 5 vertices without indices (3 triangles, all facing +Z).
    # Mesh 1: TRIANGLE_FAN of 5 vertices with u16 indices (3 triangles, all facing +Z).
    # Mesh 2: LINES (skipped by the loader with a warning).
    strip = floats([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0])
    strip_n = floats([0, 0, 1] * 5)
    fan = floats([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0])
    fan_idx = struct.pack("<5H", 0, 1, 2, 3, 4)
    data, spans = layout([strip, strip_n, fan, fan_idx])
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    doc = {
        "asset": {"version": "2.0", "generator": "clpt tests/data/valid/make_valid.py"},
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "StripByMatrix", "mesh": 0,
             "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1]},
            {"name": "Fan", "mesh": 1, "translation": [10, 0, 0]},
            {"name": "MirroredStrip", "mesh": 0, "scale": [-1, 1, 1], "translation": [20, 0, 0]},
            {"name": "Lines", "mesh": 2},
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "mode": 5}]},
            {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "mode": 6}]},
            {"primitives": [{"attributes": {"POSITION": 0}, "mode": 1}]},
        ],
        "buffers": [{"uri": uri, "byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in spans],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 2, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 5, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 5, "type": "VEC3",
             "min": [-1, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 3, "componentType": 5123, "count": 5, "type": "SCALAR"},
        ],
    }
    write_json("strip_fan.gltf", doc)


def triangle_doc(embedded_uri=None):
    pos = floats([0, 0, 0, 1, 0, 0, 0, 1, 0])
    data, spans = layout([pos])
    buf = {"byteLength": len(data)}
    if embedded_uri:
        buf["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    doc = {
        "asset": {"version": "2.0", "generator": "clpt tests/data/valid/make_valid.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [buf],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(data)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
    }
    return doc, data


def magic_not_extension():
    # A real GLB named .gltf, and a JSON glTF named .glb: the loader must go by the first bytes.
    doc, data = triangle_doc()
    with open(os.path.join(HERE, "glb_content.gltf"), "wb") as f:
        f.write(glb(doc, data))
    doc, _ = triangle_doc(embedded_uri=True)
    write_json("json_content.glb", doc)


def uris():
    # Percent-encoded buffer URI ("_" as %5F), a '+' in a file name (tinygltf 2.7 decodes '+' as a
    # space), and images that are broken, missing or undecodable: none of these may fail the load.
    doc, data = triangle_doc()
    with open(os.path.join(HERE, "plus+sign.bin"), "wb") as f:
        f.write(data)
    doc["buffers"][0]["uri"] = "plus+sign.bin"
    write_json("plus_uri.gltf", doc)

    doc, data = triangle_doc()
    with open(os.path.join(HERE, "percent_target.bin"), "wb") as f:
        f.write(data)
    doc["buffers"][0]["uri"] = "percent%5Ftarget.bin"
    doc["images"] = [
        {"uri": "not_a_png.png"},                       # exists, but is not a PNG
        {"uri": "absent%20image.png"},                  # does not exist
        {"uri": "data:image/png;base64,aGVsbG8="},      # decodes to "hello"
        {"uri": "data:image/webp;base64,UklGRg=="},     # a media type tinygltf does not know
    ]
    with open(os.path.join(HERE, "not_a_png.png"), "wb") as f:
        f.write(b"hello, I am not a PNG\n")
    doc["textures"] = [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}]
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                         "normalTexture": {"index": 1}, "emissiveTexture": {"index": 2}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    write_json("percent_uri_broken_images.gltf", doc)


if __name__ == "__main__":
    quad_trs_u8()
    strip_fan()
    magic_not_extension()
    uris()
