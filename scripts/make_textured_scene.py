#!/usr/bin/env python3
"""Writes scenes/textured-room.gltf and its textures (scenes/textures/*.png):
the bundled scene that exercises what real glTF assets use, all of it
procedural so nothing is downloaded.

- A tiled floor: base-colour texture (sRGB) and metallic-roughness texture
  (rough grout, smoother glazed tiles), its texture coordinates repeating.
- A brick wall on the right: base-colour texture and a tangent-space normal
  map made from the bricks' height field (tangents made by the loader).
- A screen of leaves on the left: an RGBA base-colour texture with
  alphaMode MASK, so the sun's light falls through between the leaves.
- A glass sphere (KHR_materials_transmission + _volume, ior 1.5) casting a
  caustic onto the floor.
- Lit by scenes/environments/sunny.pfm (scene extras.environment), written
  here: make_environment.py's sky with a sun ten times as bright (radiance
  5000, about 9x the sky's irradiance), 35 degrees high behind the screen,
  so the leaves cast sharp shadows and the sphere a caustic.

  scripts/make_textured_scene.py [--size 256]

Standard library only (PNG: zlib, 8-bit RGB/RGBA; the mesh buffer is an
embedded base64 data URI). Deterministic output.
"""
import argparse
import base64
import json
import math
import os
import struct
import sys
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_environment  # noqa: E402 (the sky, with a brighter sun)


def write_png(path, width, height, pixels, channels):
    """pixels: rows of per-pixel tuples of floats in [0, 1] (stored as given)."""
    raw = bytearray()
    for row in pixels:
        raw.append(0)  # filter: none
        for p in row:
            raw.extend(max(0, min(255, int(round(c * 255)))) for c in p[:channels])

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    colour_type = 6 if channels == 4 else 2
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def hash01(*values):
    """A deterministic number in [0, 1) from integers (texture variation)."""
    h = 2166136261
    for v in values:
        h = ((h ^ (v & 0xFFFFFFFF)) * 16777619) & 0xFFFFFFFF
    h ^= h >> 13
    h = (h * 0x5BD1E995) & 0xFFFFFFFF
    h ^= h >> 15
    return h / 4294967296.0


def floor_textures(n):
    """Tiles: 4 x 4 per texture repeat, grout lines, per-tile colour variation.
    Returns (albedo sRGB-encoded, metallic-roughness data)."""
    albedo, mr = [], []
    for y in range(n):
        arow, mrow = [], []
        for x in range(n):
            tx, ty = x * 4 // n, y * 4 // n
            fx, fy = (x * 4 / n) % 1, (y * 4 / n) % 1
            grout = min(fx, fy, 1 - fx, 1 - fy) < 0.035
            if grout:
                arow.append((0.55, 0.53, 0.5))
                mrow.append((0, 0.95, 0))
            else:
                v = 0.85 + 0.15 * hash01(tx, ty)
                warm = (0.78 * v, 0.52 * v, 0.36 * v) if (tx + ty) % 2 == 0 else (0.86 * v, 0.8 * v, 0.7 * v)
                arow.append(warm)
                mrow.append((0, 0.25 + 0.15 * hash01(ty, tx, 7), 0))
        albedo.append(arow)
        mr.append(mrow)
    return albedo, mr


def brick_textures(n):
    """Bricks in running bond, 8 rows per texture; albedo and a normal map
    from the height field (bricks 1, mortar 0, bevelled edges)."""
    rows, per_row = 8, 4

    def height(x, y):
        v = (y / n) * rows
        row = int(math.floor(v))
        u = (x / n) * per_row + (0.5 if row % 2 else 0.0)
        fu, fv = u % 1, v % 1
        edge = min(fu * 4, (1 - fu) * 4, fv * 2, (1 - fv) * 2)  # in brick-height units
        return max(0.0, min(1.0, (edge - 0.06) / 0.12)), row, int(math.floor(u))

    albedo, normal = [], []
    strength = 3.0
    for y in range(n):
        arow, nrow = [], []
        for x in range(n):
            h, row, col = height(x, y)
            if h <= 0:
                arow.append((0.6, 0.58, 0.55))
            else:
                v = 0.8 + 0.2 * hash01(row, col % per_row)
                arow.append((0.62 * v, 0.3 * v, 0.22 * v))
            # Central differences with wrap-around: the texture repeats.
            dx = height((x + 1) % n, y)[0] - height((x - 1) % n, y)[0]
            dy = height(x, (y + 1) % n)[0] - height(x, (y - 1) % n)[0]
            # +X along +u (x), +Y "up" in the image, which is -v (rows go down).
            nx, ny, nz = -strength * dx, strength * dy, 1.0
            length = math.sqrt(nx * nx + ny * ny + nz * nz)
            nrow.append((0.5 + 0.5 * nx / length, 0.5 + 0.5 * ny / length, 0.5 + 0.5 * nz / length))
        albedo.append(arow)
        normal.append(nrow)
    return albedo, normal


def leaf_texture(n):
    """Leaves: ellipses at hashed positions and angles; alpha 1 inside, 0 outside."""
    leaves = []
    for i in range(28):
        cx, cy = hash01(i, 1), hash01(i, 2)
        angle = math.pi * hash01(i, 3)
        leaves.append((cx, cy, math.cos(angle), math.sin(angle), 0.11 + 0.05 * hash01(i, 4), 0.35 + 0.4 * hash01(i, 5)))
    pixels = []
    for y in range(n):
        row = []
        for x in range(n):
            u, v = (x + 0.5) / n, (y + 0.5) / n
            inside = None
            for (cx, cy, c, s, a, shade) in leaves:
                du, dv = u - cx, v - cy
                p, q = du * c + dv * s, -du * s + dv * c
                if (p / a) ** 2 + (q / (0.4 * a)) ** 2 <= 1:
                    inside = shade
            row.append((0.15 + 0.2 * inside, 0.35 + 0.4 * inside, 0.1, 1.0) if inside is not None else (0, 0, 0, 0))
        pixels.append(row)
    return pixels


class Mesh:
    """Accumulates one glTF mesh's vertex data (positions, normals, UVs, indices)."""

    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def vertex(self, p, n, uv):
        self.positions.append(p)
        self.normals.append(n)
        self.uvs.append(uv)
        return len(self.positions) - 1

    def quad(self, origin, edge_u, edge_v, uv_scale=(1, 1)):
        """The parallelogram origin + s edge_u + t edge_v; front face along edge_u x edge_v;
        texture u along edge_u, v down from its far edge (glTF: v = 0 at the image's top)."""
        n = cross(edge_u, edge_v)
        length = math.sqrt(sum(c * c for c in n))
        n = tuple(c / length for c in n)
        corners = []
        for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
            p = tuple(origin[k] + s * edge_u[k] + t * edge_v[k] for k in range(3))
            corners.append(self.vertex(p, n, (s * uv_scale[0], (1 - t) * uv_scale[1])))
        a, b, c, d = corners
        self.indices += [a, b, c, a, c, d]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def sphere(centre, radius, rings=48, segments=96):
    m = Mesh()
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            m.vertex(tuple(centre[k] + radius * n[k] for k in range(3)), n, (j / segments, i / rings))
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j
            b, c, d = a + segments + 1, a + segments + 2, a + 1
            m.indices += [a, d, c, a, c, b]  # counter-clockwise seen from outside
    return m


def build(size):
    tex_dir = os.path.join(ROOT, "scenes", "textures")
    os.makedirs(tex_dir, exist_ok=True)
    albedo, mr = floor_textures(size)
    write_png(os.path.join(tex_dir, "floor-albedo.png"), size, size, albedo, 3)
    write_png(os.path.join(tex_dir, "floor-roughness.png"), size, size, mr, 3)
    albedo, normal = brick_textures(size)
    write_png(os.path.join(tex_dir, "bricks-albedo.png"), size, size, albedo, 3)
    write_png(os.path.join(tex_dir, "bricks-normal.png"), size, size, normal, 3)
    write_png(os.path.join(tex_dir, "leaves.png"), size, size, leaf_texture(size), 4)
    make_environment.write_sky(os.path.join(ROOT, "scenes", "environments", "sunny.pfm"), 256, sun_radiance=5000.0)

    floor, wall, screen = Mesh(), Mesh(), Mesh()
    floor.quad((-8, 0, 6), (16, 0, 0), (0, 0, -18), uv_scale=(8, 9))   # y = 0, facing +y
    wall.quad((2.5, 0, -3), (0, 0, 6), (0, 2.5, 0), uv_scale=(3, 1.25))  # x = 2.5, facing -x
    screen.quad((-2.6, 0.15, -1.6), (2.2, 0, 0.4), (0, 2.0, 0))          # leaning screen, facing +z-ish
    glass = sphere((0.5, 0.55, 1.6), 0.55)

    meshes = [("floor", floor, 0), ("brick wall", wall, 1), ("leaf screen", screen, 2), ("glass sphere", glass, 3)]
    blob = bytearray()
    views, accessors, gltf_meshes = [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for name, m, material in meshes:
        attributes = {}
        for key, values, kind in (("POSITION", m.positions, "VEC3"), ("NORMAL", m.normals, "VEC3"),
                                  ("TEXCOORD_0", m.uvs, "VEC2")):
            flat = [c for v in values for c in v]
            view = add_view(struct.pack("<%df" % len(flat), *flat), 34962)
            accessor = {"bufferView": view, "componentType": 5126, "count": len(values), "type": kind}
            if key == "POSITION":
                accessor["min"] = [min(v[k] for v in values) for k in range(3)]
                accessor["max"] = [max(v[k] for v in values) for k in range(3)]
            accessors.append(accessor)
            attributes[key] = len(accessors) - 1
        view = add_view(struct.pack("<%dI" % len(m.indices), *m.indices), 34963)
        accessors.append({"bufferView": view, "componentType": 5125, "count": len(m.indices), "type": "SCALAR"})
        gltf_meshes.append({"name": name, "primitives": [{"attributes": attributes, "indices": len(accessors) - 1,
                                                           "material": material}]})

    dim_specular = {"KHR_materials_specular": {"specularFactor": 0.25}}
    doc = {
        "asset": {"version": "2.0", "generator": "wavevcm scripts/make_textured_scene.py"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_volume"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(meshes) + 1)),
                    "extras": {"environment": {"uri": "environments/sunny.pfm", "strength": 0.3, "rotation": 0}}}],
        "nodes": [{"name": name, "mesh": i} for i, (name, _, _) in enumerate(meshes)] + [
            {"name": "camera", "camera": 0, "translation": [-0.2, 2.0, 6.3],
             # looking down by 15 degrees: a rotation about +x
             "rotation": [-math.sin(math.radians(7.5)), 0, 0, math.cos(math.radians(7.5))]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.75, "aspectRatio": 1.5, "znear": 0.05}}],
        "meshes": gltf_meshes,
        "materials": [
            {"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                      "metallicRoughnessTexture": {"index": 1},
                                                      "metallicFactor": 0.0, "roughnessFactor": 1.0},
             "extensions": dim_specular},
            {"name": "bricks", "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}, "metallicFactor": 0.0,
                                                       "roughnessFactor": 0.9},
             "normalTexture": {"index": 3, "scale": 1.0}, "extensions": dim_specular},
            {"name": "leaves", "pbrMetallicRoughness": {"baseColorTexture": {"index": 4}, "metallicFactor": 0.0,
                                                       "roughnessFactor": 0.8},
             "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True, "extensions": dim_specular},
            {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                                      "roughnessFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                            "KHR_materials_ior": {"ior": 1.5},
                            "KHR_materials_volume": {"thicknessFactor": 1.0}}},
        ],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "textures/" + f} for f in ("floor-albedo.png", "floor-roughness.png", "bricks-albedo.png",
                                                      "bricks-normal.png", "leaves.png")],
        "textures": [{"source": i, "sampler": 0} for i in range(5)],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    path = os.path.join(ROOT, "scenes", "textured-room.gltf")
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(path)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=256, help="texture width and height")
    build(p.parse_args().size)


if __name__ == "__main__":
    main()
