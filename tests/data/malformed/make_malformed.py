#!/usr/bin/env python3
"""Writes the malformed glTF corpus used by tests/gltf_loader_test.cpp (python3, standard library).

Each output is a small, broken variant of one valid triangle. README.md lists every file with
the fragment of the error message the loader must produce; the test has the same table.
Run it from anywhere; it writes next to itself. The outputs are committed.
"""
import base64
import copy
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
F32 = 5126
U8 = 5121
U16 = 5123


def layout(chunks):
    data = b""
    spans = []
    for c in chunks:
        data += b"\0" * (-len(data) % 4)
        spans.append((len(data), len(c)))
        data += c
    data += b"\0" * (-len(data) % 4)
    return data, spans


def data_uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def triangle(positions=(0, 0, 0, 1, 0, 0, 0, 1, 0), indices=(0, 1, 2), extra=()):
    """A valid indexed triangle with an embedded buffer. `extra` chunks get bufferViews 2, 3, ..."""
    pos = struct.pack("<9f", *positions)
    idx = struct.pack("<3H", *indices)
    data, spans = layout([pos, idx] + list(extra))
    return {
        "asset": {"version": "2.0", "generator": "clpt tests/data/malformed/make_malformed.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": data_uri(data), "byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in spans],
        "accessors": [
            {"bufferView": 0, "componentType": F32, "count": 3, "type": "VEC3"},
            {"bufferView": 1, "componentType": U16, "count": 3, "type": "SCALAR"},
        ],
    }, data


def glb(doc, bin_data, json_type=b"JSON", bin_type=b"BIN\0", version=2, length_delta=0,
        json_length=None):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<I", len(js) if json_length is None else json_length) + json_type + js
    if bin_data is not None:
        body += struct.pack("<I", len(bin_data)) + bin_type + bin_data
    return b"glTF" + struct.pack("<II", version, 12 + len(body) + length_delta) + body


def glb_triangle():
    doc, data = triangle()
    del doc["buffers"][0]["uri"]
    return doc, data


def write(name, content):
    if isinstance(content, dict):
        content = (json.dumps(content, indent=1) + "\n").encode()
    elif isinstance(content, str):
        content = content.encode()
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(content)


def variant(name, mutate, **kw):
    doc, _ = triangle(**kw)
    mutate(doc)
    write(name, doc)


def main():
    # --- accessors and buffer views
    variant("accessor_overrun.gltf", lambda d: d["accessors"][0].update(count=4))
    variant("bufferview_overrun.gltf", lambda d: d["bufferViews"][1].update(byteLength=100))
    # 12 * (2^62 + 1) wraps to 12 in 64-bit arithmetic: a naive end-of-range check would pass.
    variant("huge_count.gltf", lambda d: d["accessors"][0].update(count=2**62 + 1))
    variant("huge_byte_offset.gltf", lambda d: d["accessors"][0].update(byteOffset=2**63))
    variant("stride_too_small.gltf", lambda d: d["bufferViews"][0].update(byteStride=4))
    variant("wrong_accessor_type.gltf", lambda d: d["accessors"][0].update(type="VEC2"))
    variant("float_indices.gltf", lambda d: d["accessors"][1].update(componentType=F32, count=1))
    variant("index_out_of_range.gltf", lambda d: None, indices=(0, 1, 7))
    variant("nan_position.gltf", lambda d: None, positions=(0, 0, 0, float("nan"), 0, 0, 0, 1, 0))
    variant("invalid_accessor_index.gltf",
            lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(POSITION=9))
    variant("missing_position.gltf",
            lambda d: d["meshes"][0]["primitives"][0].update(attributes={"NORMAL": 0}))
    variant("bad_mode.gltf", lambda d: d["meshes"][0]["primitives"][0].update(mode=9))

    def sparse(d):
        # Sparse substitution whose index (5) is outside the accessor's 3 elements.
        d["accessors"][0]["sparse"] = {"count": 1,
                                       "indices": {"bufferView": 2, "componentType": U16},
                                       "values": {"bufferView": 3}}
    variant("sparse_index_out_of_range.gltf", sparse,
            extra=[struct.pack("<H", 5), struct.pack("<3f", 9, 9, 9)])

    # --- URIs and external files
    def uri(u, n=None):
        def f(d):
            d["buffers"][0]["uri"] = u
            if n is not None:
                d["buffers"][0]["byteLength"] = n
        return f
    # ../valid/quad_trs_u8.bin exists and has that size: only the folder rule can refuse it.
    variant("uri_parent_escape.gltf", uri("../valid/quad_trs_u8.bin", 120))
    variant("uri_percent_escape.gltf", uri("%2E%2E/valid/quad_trs_u8.bin", 120))
    variant("uri_absolute.gltf", uri("/etc/passwd"))
    variant("uri_http.gltf", uri("http://example.com/triangle.bin"))
    variant("uri_file_scheme.gltf", uri("file:///etc/passwd"))
    variant("missing_bin.gltf", uri("missing.bin"))
    _, data = triangle()
    write("triangle.bin", data)
    variant("bin_size_mismatch.gltf", uri("triangle.bin", len(data) + 4))

    # --- extensions
    def require(ext):
        def f(d):
            d["extensionsUsed"] = [ext]
            d["extensionsRequired"] = [ext]
        return f
    variant("basisu_required.gltf", require("KHR_texture_basisu"))

    # --- compressed and quantized geometry (host/scene/gltf/compression.cpp, accessors.cpp).
    # Valid Draco and meshopt data come from their encoders in tests/compressed_geometry_test.cpp;
    # these are the cases a few JSON fields and bytes can make.
    variant("quantized_without_extension.gltf",
            lambda d: d["accessors"][0].update(componentType=U16))
    def meshopt(fields, chunk=b"\xa0" + b"\0" * 15):
        def f(d):
            require("EXT_meshopt_compression")(d)
            # bufferView 2 (16 bytes of `chunk`) holds the "compressed" positions.
            ext = {"buffer": 0, "byteOffset": d["bufferViews"][2]["byteOffset"], "byteLength": 16,
                   "byteStride": 12, "count": 3, "mode": "ATTRIBUTES"}
            ext.update(fields)
            d["bufferViews"][0]["extensions"] = {"EXT_meshopt_compression": ext}
        return f, [chunk]
    for name, fields in [("meshopt_bad_mode.gltf", {"mode": "STRIPS"}),
                         ("meshopt_bad_stride.gltf", {"byteStride": 6}),
                         ("meshopt_past_buffer.gltf", {"byteLength": 4096}),
                         ("meshopt_count_over_limit.gltf", {"count": 2**31 - 1}),
                         ("meshopt_garbage.gltf", {"byteStride": 12})]:
        f, extra = meshopt(fields, chunk=b"\x55" * 16 if name == "meshopt_garbage.gltf" else b"\xa0" + b"\0" * 15)
        variant(name, f, extra=extra)
    def draco(d):
        require("KHR_draco_mesh_compression")(d)
        d["meshes"][0]["primitives"][0]["extensions"] = {
            "KHR_draco_mesh_compression": {"bufferView": 2, "attributes": {"POSITION": 0}}}
        for a in d["accessors"]:
            del a["bufferView"]
    variant("draco_garbage.gltf", draco, extra=[b"DRACO\x02\x02\x01\x01\x00" + b"\xff" * 22])

    # --- KHR_lights_punctual (host/scene/gltf_lights.cpp): one light on node 1
    def lit(light, node_ext=None):
        def f(d):
            require("KHR_lights_punctual")(d)
            d["extensions"] = {"KHR_lights_punctual": {"lights": [light]}}
            ext = {"light": 0} if node_ext is None else node_ext
            d["nodes"].append({"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": ext}})
            d["scenes"][0]["nodes"].append(1)
        return f
    variant("lights_bad_type.gltf", lit({"type": "area"}))
    variant("lights_negative_intensity.gltf", lit({"type": "point", "intensity": -1}))
    variant("lights_bad_color.gltf", lit({"type": "point", "color": [1, 1]}))
    variant("lights_cone_order.gltf",
            lit({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.25}}))
    variant("lights_cone_too_wide.gltf", lit({"type": "spot", "spot": {"outerConeAngle": 2}}))
    variant("lights_spot_without_cone.gltf", lit({"type": "spot"}))
    variant("lights_index_out_of_range.gltf", lit({"type": "point"}, {"light": 3}))
    variant("lights_node_without_index.gltf", lit({"type": "point"}, {}))
    # color and intensity each fit a float, their product does not (issue 23, class 9)
    variant("lights_power_overflow.gltf",
            lit({"type": "point", "color": [1e30, 1, 1], "intensity": 1e30}))

    # --- scenes and nodes
    variant("empty_scene.gltf", lambda d: d["scenes"][0].update(nodes=[]))
    write("no_scenes_no_nodes.gltf", {"asset": {"version": "2.0"}})
    variant("default_scene_out_of_range.gltf", lambda d: d.update(scene=4))
    variant("invalid_node_index.gltf", lambda d: d["scenes"][0].update(nodes=[5]))
    variant("invalid_mesh_index.gltf", lambda d: d["nodes"][0].update(mesh=3))
    variant("node_cycle.gltf", lambda d: d.update(nodes=[{"children": [1]}, {"children": [0], "mesh": 0}]))
    variant("node_self_child.gltf", lambda d: d["nodes"][0].update(children=[0]))
    variant("deep_hierarchy.gltf",
            lambda d: d.update(nodes=[{"children": [i + 1]} for i in range(1100)] + [{"mesh": 0}]))
    variant("zero_quaternion.gltf", lambda d: d["nodes"][0].update(rotation=[0, 0, 0, 0]))
    # indices tinygltf keeps in int: 2^32 became 0, -5 "no default scene" (issue 23, class 6)
    variant("index_past_32_bits.gltf", lambda d: d["nodes"][0].update(mesh=2**32))
    variant("negative_default_scene.gltf", lambda d: d.update(scene=-5))
    # finite as a double, past a float's range: a camera or light there sat at infinity
    # (issue 23, class 9)
    def far_camera(d):
        d["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}]
        d["nodes"].append({"camera": 0, "translation": [1e39, 0, 0]})
        d["scenes"][0]["nodes"].append(1)
    variant("camera_past_float_range.gltf", far_camera)
    variant("matrix_wrong_size.gltf", lambda d: d["nodes"][0].update(matrix=[1, 0, 0, 0, 1, 0]))

    # --- JSON level
    doc, _ = triangle()
    text = json.dumps(doc, indent=1)
    write("invalid_json.gltf", text.replace('"scenes":', '"scenes" ', 1))
    write("truncated.gltf", text[: len(text) // 2])
    write("zero_bytes.gltf", b"")
    write("not_an_object.gltf", "[1, 2, 3]\n")
    variant("gltf_version_1.gltf", lambda d: d["asset"].update(version="1.0"))
    write("deep_nesting.gltf", text[:-2] + ', "extras": ' + "[" * 10000 + "]" * 10000 + "\n}\n")

    # --- GLB container
    doc, data = glb_triangle()
    good = glb(doc, data)
    write("glb_length_lie.glb", glb(doc, data, length_delta=100))
    write("glb_length_short.glb", glb(doc, data, length_delta=-8))
    write("glb_truncated.glb", good[: len(good) - 20])
    write("glb_header_only.glb", good[:8])
    write("glb_version_1.glb", glb(doc, data, version=1))
    write("glb_bad_chunk_type.glb", glb(doc, data, json_type=b"JSNO"))
    write("glb_chunk_length_overrun.glb", glb(doc, data, json_length=0xFFFFFFF0))
    write("glb_bad_bin_chunk.glb", glb(doc, data, bin_type=b"XYZ\0"))
    doc2 = copy.deepcopy(doc)
    doc2["buffers"][0]["byteLength"] = len(data) + 64
    write("glb_bin_too_short.glb", glb(doc2, data))

    # --- textures (decoded by host/scene/image_decode.cpp)
    def png_chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload +
                struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF))

    def png(width, height, rows=None):
        """An 8-bit RGB PNG; rows=None gives a valid header with an empty image stream."""
        ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
        raw = zlib.compress(rows if rows is not None else b"")
        return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", raw) +
                png_chunk(b"IEND", b""))

    def textured(image_uri=None, texture=0, tex_coord=None, image=None):
        def f(d):
            info = {"index": texture}
            if tex_coord is not None:
                info["texCoord"] = tex_coord
            d["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": info}}]
            d["meshes"][0]["primitives"][0]["material"] = 0
            d["textures"] = [{"source": 0}]
            d["images"] = [image if image is not None else {"uri": image_uri}]
        return f

    def png_uri(data):
        return "data:image/png;base64," + base64.b64encode(data).decode()

    good_png = png(1, 1, b"\0\xff\0\0")
    variant("texture_bad_image.gltf", textured(png_uri(good_png[:8] + b"this is not a PNG stream")))
    variant("texture_too_large.gltf", textured(png_uri(png(16385, 1))))
    variant("texture_index_out_of_range.gltf", textured(png_uri(good_png), texture=5))
    variant("texture_texcoord_7.gltf", textured(png_uri(good_png), tex_coord=7))
    # A material extension whose colour is not a colour (materials.cpp's ext_color).
    def sheen(d):
        d["materials"] = [{"extensions": {"KHR_materials_sheen": {"sheenColorFactor": "red"}}}]
        d["meshes"][0]["primitives"][0]["material"] = 0
        d["extensionsUsed"] = ["KHR_materials_sheen"]
    variant("sheen_bad_color.gltf", sheen)
    # An anisotropy whose rotation is not a number (materials.cpp's ext_number).
    def anisotropy(d):
        d["materials"] = [{"extensions": {"KHR_materials_anisotropy": {"anisotropyRotation": "north"}}}]
        d["meshes"][0]["primitives"][0]["material"] = 0
        d["extensionsUsed"] = ["KHR_materials_anisotropy"]
    variant("anisotropy_bad_rotation.gltf", anisotropy)

    # A dispersion that is not a number.
    def dispersion(d):
        d["materials"] = [{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                          "KHR_materials_dispersion": {"dispersion": [1]}}}]
        d["meshes"][0]["primitives"][0]["material"] = 0
        d["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_dispersion"]
        d["extensionsRequired"] = ["KHR_materials_dispersion"]
    variant("dispersion_not_a_number.gltf", dispersion)
    # The clearcoat's normal map with a scale that is not a number (its normalTextureInfo).
    def coat_normal_scale(d):
        textured(png_uri(good_png))(d)
        d["materials"] = [{"extensions": {"KHR_materials_clearcoat": {
            "clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 0, "scale": "big"}}}}]
        d["extensionsUsed"] = ["KHR_materials_clearcoat"]
    variant("clearcoat_normal_bad_scale.gltf", coat_normal_scale)
    # An image in a bufferView that runs past its buffer (tinygltf passes such a pointer on
    # unchecked; clpt reads images only through its checked bufferView accessor).
    doc, data = glb_triangle()
    textured(image={"bufferView": 2, "mimeType": "image/png"})(doc)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": 40, "byteLength": 4096})
    write("texture_bufferview_overrun.glb", glb(doc, data))


if __name__ == "__main__":
    main()
