#!/usr/bin/env python3
"""Generate the Cornell box test scene used by wavevcm.

The scene is a classic Cornell box (interior x in [-1, 1], y in [0, 2],
z in [-1, 1], open towards +Z) with white floor, ceiling and back wall, a red
left wall, a green right wall, a small downward-facing area light just below
the ceiling, a mirror sphere and a glass sphere, plus a perspective camera.
It is written as a single self-contained glTF 2.0 file (buffer embedded as a
base64 data URI) and exercises TRS and matrix node transforms, a node
hierarchy, shared accessors and several KHR_materials_* extensions.

Usage (from the repository root):

    python3 scripts/make_cornell_box.py            # writes scenes/cornell-box.gltf
    python3 scripts/make_cornell_box.py -o out.gltf

Only the Python standard library is used and the output is deterministic.
"""

import argparse
import base64
import json
import math
import os
import struct

FLOAT, UINT = 5126, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963

WHITE = [0.725, 0.71, 0.68, 1.0]
RED = [0.63, 0.065, 0.05, 1.0]
GREEN = [0.14, 0.45, 0.091, 1.0]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def normalize(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def quad(origin, u, v):
    """Quad with corners origin, +u, +u+v, +v; its normal is cross(u, v)."""
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    positions = [tuple(o + a * du + b * dv for o, du, dv in zip(origin, u, v))
                 for a, b in corners]
    normal = normalize(cross(u, v))
    return positions, [normal] * 4, [0, 1, 2, 0, 2, 3]


def uv_sphere(segments=32, rings=16):
    """Unit sphere: a vertex at each pole, rings-1 latitude rings in between."""
    positions = [(0.0, 1.0, 0.0)]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            positions.append((math.sin(theta) * math.cos(phi),
                              math.cos(theta),
                              math.sin(theta) * math.sin(phi)))
    positions.append((0.0, -1.0, 0.0))
    south = len(positions) - 1

    def ring(i, j):  # index of vertex j on latitude ring i (1..rings-1)
        return 1 + (i - 1) * segments + j % segments

    indices = []
    for j in range(segments):
        indices += [0, ring(1, j + 1), ring(1, j)]
        for i in range(1, rings - 1):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j + 1), ring(i + 1, j)
            indices += [a, b, d, b, c, d]
        indices += [ring(rings - 1, j), ring(rings - 1, j + 1), south]
    return positions, list(positions), indices


class GltfBuilder:
    """Packs geometry into one binary buffer and tracks glTF arrays."""

    def __init__(self):
        self.data = bytearray()
        self.buffer_views = []
        self.accessors = []

    def _add(self, fmt, values, target, count, accessor):
        while len(self.data) % 4:
            self.data.append(0)
        packed = struct.pack("<%d%s" % (len(values), fmt), *values)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.data),
                                  "byteLength": len(packed), "target": target})
        self.data += packed
        accessor.update({"bufferView": len(self.buffer_views) - 1,
                         "byteOffset": 0, "count": count})
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def add_vec3(self, vectors, with_bounds=False):
        flat = [c for v in vectors for c in v]
        accessor = {"componentType": FLOAT, "type": "VEC3"}
        if with_bounds:
            # Bounds must match the stored float32 values exactly.
            stored = struct.unpack("<%df" % len(flat),
                                   struct.pack("<%df" % len(flat), *flat))
            accessor["min"] = [min(stored[k::3]) for k in range(3)]
            accessor["max"] = [max(stored[k::3]) for k in range(3)]
        return self._add("f", flat, ARRAY_BUFFER, len(vectors), accessor)

    def add_indices(self, indices):
        accessor = {"componentType": UINT, "type": "SCALAR"}
        return self._add("I", indices, ELEMENT_ARRAY_BUFFER, len(indices),
                         accessor)

    def add_geometry(self, positions, normals, indices):
        """Returns primitive attributes/indices (without material)."""
        return {"attributes": {"POSITION": self.add_vec3(positions, True),
                               "NORMAL": self.add_vec3(normals)},
                "indices": self.add_indices(indices)}


def diffuse(name, color):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": color,
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}


def build_scene():
    materials = [
        diffuse("white", WHITE),
        diffuse("red", RED),
        diffuse("green", GREEN),
        {"name": "light",
         "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                  "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0},
         "emissiveFactor": [1.0, 0.85, 0.6],
         "extensions": {
             "KHR_materials_emissive_strength": {"emissiveStrength": 40.0},
             "KHR_materials_specular": {"specularFactor": 0.0}}},
        {"name": "mirror",
         "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1.0],
                                  "metallicFactor": 1.0,
                                  "roughnessFactor": 0.0}},
        {"name": "glass",
         "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                  "metallicFactor": 0.0,
                                  "roughnessFactor": 0.0},
         "extensions": {
             "KHR_materials_ior": {"ior": 1.5},
             "KHR_materials_transmission": {"transmissionFactor": 1.0},
             "KHR_materials_volume": {"thicknessFactor": 1.0}}},
    ]
    material_index = {m["name"]: i for i, m in enumerate(materials)}

    # (name, material, origin, u, v): the normal cross(u, v) faces the interior.
    quads = [
        ("floor", "white", (-1, 0, -1), (0, 0, 2), (2, 0, 0)),
        ("ceiling", "white", (-1, 2, -1), (2, 0, 0), (0, 0, 2)),
        ("back_wall", "white", (-1, 0, -1), (2, 0, 0), (0, 2, 0)),
        ("left_wall", "red", (-1, 0, -1), (0, 2, 0), (0, 0, 2)),
        ("right_wall", "green", (1, 0, -1), (0, 0, 2), (0, 2, 0)),
        ("light", "light", (-0.25, 1.98, -0.2), (0.5, 0, 0), (0, 0, 0.4)),
    ]

    builder = GltfBuilder()
    meshes, nodes = [], []
    for name, material, origin, u, v in quads:
        primitive = builder.add_geometry(*quad(origin, u, v))
        primitive["material"] = material_index[material]
        nodes.append({"name": name, "mesh": len(meshes)})
        meshes.append({"name": name, "primitives": [primitive]})

    sphere = builder.add_geometry(*uv_sphere())
    spheres = [("mirror_sphere", "mirror", [-0.45, 0.4, -0.3], 0.4),
               ("glass_sphere", "glass", [0.5, 0.35, 0.35], 0.35)]
    sphere_nodes = []
    for name, material, translation, radius in spheres:
        primitive = dict(sphere, material=material_index[material])
        sphere_nodes.append(len(nodes))
        nodes.append({"name": name, "mesh": len(meshes),
                      "translation": translation, "scale": [radius] * 3})
        meshes.append({"name": name, "primitives": [primitive]})

    identity = [1.0 if row == col else 0.0
                for col in range(4) for row in range(4)]
    nodes.append({"name": "objects", "matrix": identity,
                  "children": sphere_nodes})
    nodes.append({"name": "camera", "camera": 0,
                  "translation": [0.0, 1.0, 3.9]})

    children = set(sphere_nodes)
    roots = [i for i in range(len(nodes)) if i not in children]
    extensions = sorted({ext for m in materials
                         for ext in m.get("extensions", {})})
    data = bytes(builder.data)
    return {
        "asset": {"version": "2.0",
                  "generator": "wavevcm scripts/make_cornell_box.py"},
        "extensionsUsed": extensions,
        "scene": 0,
        "scenes": [{"name": "cornell_box", "nodes": roots}],
        "nodes": nodes,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 0.68, "aspectRatio": 1.0,
                                     "znear": 0.01, "zfar": 100.0}}],
        "meshes": meshes,
        "materials": materials,
        "accessors": builder.accessors,
        "bufferViews": builder.buffer_views,
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(data).decode("ascii")}],
    }


def main():
    repo_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output",
                        default=os.path.join(repo_root, "scenes",
                                             "cornell-box.gltf"),
                        help="output .gltf path (default: %(default)s)")
    args = parser.parse_args()
    with open(args.output, "w", encoding="utf-8", newline="\n") as f:
        f.write(json.dumps(build_scene(), indent=1) + "\n")


if __name__ == "__main__":
    main()
