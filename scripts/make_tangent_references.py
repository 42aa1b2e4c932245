#!/usr/bin/env python3
"""Reference tangents for the loader's MikkTSpace test (tests/data/mikktspace-*.gltf).

Blender computes tangents with MikkTSpace, the algorithm the glTF specification
recommends for primitives without TANGENT, and its glTF exporter writes them.
This script builds three triangulated, smooth-shaded meshes with UVs in Blender
(Suzanne with its mirrored UV layout, a UV sphere with seams and poles, a
grid bent into a wave with a UV island mirrored by hand), exports each with
POSITION, NORMAL, TEXCOORD_0 and TANGENT, and gives the primitive a material
with a normal texture (a 1x1 flat normal map as a data URI), so the loader
makes tangents for it. GltfLoader.GeneratedTangentsAreMikkTSpace loads each
file once as written and once with TANGENT taken out, and compares.

Needs Blender's Python module (bpy 4.2, Python 3.11), e.g.
    python3.11 -m venv /tmp/bpy && /tmp/bpy/bin/pip install bpy==4.2.0
    /tmp/bpy/bin/python scripts/make_tangent_references.py tests/data
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

import bpy  # before bmesh, which it provides
import bmesh  # noqa: E402


def flat_normal_png():
    """A 1x1 RGB PNG of the flat normal (128, 128, 255)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    header = struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)
    pixels = zlib.compress(bytes([0, 128, 128, 255]))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", pixels) + chunk(b"IEND", b"")


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def finish(obj):
    """Triangulate (MikkTSpace treats quads differently from their triangles) and smooth-shade."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(obj.data)
    bm.free()
    for p in obj.data.polygons:
        p.use_smooth = True


def suzanne():
    bpy.ops.mesh.primitive_monkey_add(calc_uvs=True)
    return bpy.context.active_object


def sphere():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, calc_uvs=True)
    return bpy.context.active_object


def mirrored_wave():
    """A 6x6 grid bent into a wave; the UVs of its right half mirror those of the left."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6, size=2, calc_uvs=True)
    obj = bpy.context.active_object
    for v in obj.data.vertices:
        v.co.z = 0.3 * math.sin(2.0 * v.co.x) * math.cos(1.5 * v.co.y)
    uv = obj.data.uv_layers.active.data
    for loop in obj.data.loops:
        co = obj.data.vertices[loop.vertex_index].co
        u = (co.x + 1.0) / 2.0
        uv[loop.index].uv = (u if u <= 0.5 else 1.0 - u, (co.y + 1.0) / 2.0)
    return obj


def export(obj, path):
    finish(obj)
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", use_selection=True,
                              export_tangents=True, export_normals=True, export_texcoords=True,
                              export_materials="NONE", export_yup=True)
    with open(path) as f:
        doc = json.load(f)
    for buffer in doc["buffers"]:  # one self-contained file: the buffer as a data URI
        bin_path = os.path.join(os.path.dirname(path), buffer["uri"])
        with open(bin_path, "rb") as f:
            buffer["uri"] = "data:application/octet-stream;base64," + base64.b64encode(f.read()).decode()
        os.remove(bin_path)
    doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(flat_normal_png()).decode()}]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"normalTexture": {"index": 0}, "pbrMetallicRoughness": {"metallicFactor": 0.0}}]
    for mesh in doc["meshes"]:
        for prim in mesh["primitives"]:
            prim["material"] = 0
            assert "TANGENT" in prim["attributes"], "Blender wrote no tangents"
    doc["asset"]["generator"] = "scripts/make_tangent_references.py (Blender %s)" % bpy.app.version_string
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "tests/data"
    os.makedirs(out, exist_ok=True)
    for name, make in (("suzanne", suzanne), ("sphere", sphere), ("mirrored-wave", mirrored_wave)):
        reset()
        export(make(), os.path.abspath(os.path.join(out, "mikktspace-%s.gltf" % name)))
        print("wrote", os.path.join(out, "mikktspace-%s.gltf" % name))


if __name__ == "__main__":
    main()
