"""Building blocks for wavevcm's test scenes: self-contained glTF 2.0 files.

Geometry helpers return (positions, normals, indices) with counter-clockwise
(front) faces; SceneBuilder packs geometry into one embedded binary buffer and
collects materials, meshes, nodes, cameras and KHR_lights_punctual lights.
Orientations follow glTF: cameras, lights and the emissive panels made by
panel() point along their node's local -Z.

Only the Python standard library is used and the output is deterministic.
"""

import base64
import json
import math
import struct

FLOAT, UINT = 5126, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


# Vectors are tuples of three floats.

def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def normalize(v):
    length = math.sqrt(dot(v, v))
    return tuple(c / length for c in v)


# Geometry: (positions, normals, indices).

def quad(origin, u, v):
    """Quad with corners origin, +u, +u+v, +v; its normal is cross(u, v)."""
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    positions = [tuple(o + a * du + b * dv for o, du, dv in zip(origin, u, v))
                 for a, b in corners]
    normal = normalize(cross(u, v))
    return positions, [normal] * 4, [0, 1, 2, 0, 2, 3]


def panel(width, height):
    """Quad of width x height centred on the origin in the XY plane, facing -Z."""
    return quad((-width / 2, -height / 2, 0.0), (0.0, height, 0.0),
                (width, 0.0, 0.0))


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


def read_obj(path):
    """Positions and triangle indices of a Wavefront OBJ of triangles.

    Vertices at identical positions are merged (a mesh written patch by patch
    repeats the vertices along its seams), so smooth normals run across seams.
    """
    vertices, triangles = [], []
    with open(path, encoding="ascii") as f:
        for line in f:
            fields = line.split()
            if fields and fields[0] == "v":
                vertices.append(tuple(float(x) for x in fields[1:4]))
            elif fields and fields[0] == "f":
                if len(fields) != 4:
                    raise ValueError("%s: only triangles are supported" % path)
                triangles += [int(x.split("/")[0]) - 1 for x in fields[1:]]
    merged = {}
    remap = [merged.setdefault(v, len(merged)) for v in vertices]
    return list(merged), [remap[i] for i in triangles]


def signed_volume(positions, indices):
    """Volume enclosed by a closed mesh; negative when its faces point inwards."""
    return sum(dot(positions[a], cross(positions[b], positions[c]))
               for a, b, c in zip(*[iter(indices)] * 3)) / 6.0


def outward(positions, indices):
    """indices with the winding reversed if the faces point inwards."""
    if signed_volume(positions, indices) >= 0:
        return indices
    return [i for a, b, c in zip(*[iter(indices)] * 3) for i in (a, c, b)]


def smooth_normals(positions, indices):
    """Per-vertex normals: the area-weighted mean of the adjacent face normals."""
    sums = [(0.0, 0.0, 0.0)] * len(positions)
    for a, b, c in zip(*[iter(indices)] * 3):
        # cross() of two edges is the face normal scaled by twice its area.
        n = cross(sub(positions[b], positions[a]),
                  sub(positions[c], positions[a]))
        for k in (a, b, c):
            sums[k] = tuple(s + x for s, x in zip(sums[k], n))
    return [normalize(s) for s in sums]


def stand_on_floor(positions, height):
    """positions scaled to the given height, centred on the Y axis, lowest at y = 0."""
    low = [min(p[k] for p in positions) for k in range(3)]
    high = [max(p[k] for p in positions) for k in range(3)]
    s = height / (high[1] - low[1])
    centre = ((low[0] + high[0]) / 2, low[1], (low[2] + high[2]) / 2)
    return [tuple(s * (x - c) for x, c in zip(p, centre)) for p in positions]


# Orientations: glTF quaternions [x, y, z, w].

def rotation_y(degrees):
    half = math.radians(degrees) / 2
    return [0.0, math.sin(half), 0.0, math.cos(half)]


def look_rotation(forward, up=(0.0, 1.0, 0.0)):
    """Rotation taking local -Z to forward and local +Y towards up."""
    f = normalize(forward)
    r = normalize(cross(f, up))
    u = cross(r, f)
    # Columns of the rotation matrix are the images of +X, +Y and +Z.
    m = [[r[i], u[i], -f[i]] for i in range(3)]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s,
             (m[1][0] - m[0][1]) / s, s / 4]
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = [s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s,
             (m[2][1] - m[1][2]) / s]
    elif m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = [(m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s,
             (m[0][2] - m[2][0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4,
             (m[1][0] - m[0][1]) / s]
    sign = 1.0 if q[3] >= 0 else -1.0
    return [sign * c + 0.0 for c in q]  # + 0.0 turns -0.0 into 0.0


# Materials (glTF material objects; a scene stores each name once).

def diffuse(name, color):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": color,
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}


def emitter(name, color, strength):
    """Black Lambertian surface emitting radiance color x strength."""
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "emissiveFactor": color,
            "extensions": {
                "KHR_materials_emissive_strength": {"emissiveStrength":
                                                    strength},
                "KHR_materials_specular": {"specularFactor": 0.0}}}


def metal(name, color, roughness):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": color,
                                     "metallicFactor": 1.0,
                                     "roughnessFactor": roughness}}


def glass(name, ior=1.5):
    """Clear refracting solid (not thin-walled: the volume has a thickness)."""
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 0.0},
            "extensions": {
                "KHR_materials_ior": {"ior": ior},
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_volume": {"thicknessFactor": 1.0}}}


class SceneBuilder:
    """One glTF scene: geometry in one buffer, nodes in insertion order.

    Node keyword arguments (translation, rotation, scale, matrix, children,
    ...) are copied into the node in the order given. Nodes that are nobody's
    child are the scene's roots.
    """

    def __init__(self, name):
        self.name = name
        self.data = bytearray()
        self.buffer_views, self.accessors = [], []
        self.materials, self.meshes, self.nodes = [], [], []
        self.cameras, self.lights = [], []
        self.children = set()

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

    def _add_vec3(self, vectors, with_bounds=False):
        flat = [c for v in vectors for c in v]
        accessor = {"componentType": FLOAT, "type": "VEC3"}
        if with_bounds:
            # Bounds must match the stored float32 values exactly.
            stored = struct.unpack("<%df" % len(flat),
                                   struct.pack("<%df" % len(flat), *flat))
            accessor["min"] = [min(stored[k::3]) for k in range(3)]
            accessor["max"] = [max(stored[k::3]) for k in range(3)]
        return self._add("f", flat, ARRAY_BUFFER, len(vectors), accessor)

    def add_geometry(self, positions, normals, indices):
        """A primitive (without material) whose accessors meshes may share."""
        return {"attributes": {"POSITION": self._add_vec3(positions, True),
                               "NORMAL": self._add_vec3(normals)},
                "indices": self._add("I", indices, ELEMENT_ARRAY_BUFFER,
                                     len(indices),
                                     {"componentType": UINT,
                                      "type": "SCALAR"})}

    def material(self, material):
        """Index of material, added on first use (materials match by name)."""
        for i, m in enumerate(self.materials):
            if m["name"] == material["name"]:
                return i
        self.materials.append(material)
        return len(self.materials) - 1

    def add_node(self, name, **fields):
        self.children.update(fields.get("children", ()))
        self.nodes.append(dict(name=name, **fields))
        return len(self.nodes) - 1

    def add_mesh(self, name, primitive, material, **transform):
        """A one-primitive mesh and the node placing it; primitive comes
        from add_geometry() or is a (positions, normals, indices) tuple."""
        if isinstance(primitive, tuple):
            primitive = self.add_geometry(*primitive)
        self.meshes.append({"name": name, "primitives": [
            dict(primitive, material=self.material(material))]})
        return self.add_node(name, mesh=len(self.meshes) - 1, **transform)

    def add_camera(self, yfov, aspect_ratio, **transform):
        self.cameras.append({"name": "camera", "type": "perspective",
                             "perspective": {"yfov": yfov,
                                             "aspectRatio": aspect_ratio,
                                             "znear": 0.01, "zfar": 100.0}})
        return self.add_node("camera", camera=len(self.cameras) - 1,
                             **transform)

    def add_light(self, name, kind, color, intensity, **transform):
        """A KHR_lights_punctual light: kind is point, spot or directional."""
        self.lights.append({"name": name, "type": kind, "color": color,
                            "intensity": intensity})
        extension = {"KHR_lights_punctual": {"light": len(self.lights) - 1}}
        return self.add_node(name, extensions=extension, **transform)

    def gltf(self, generator, background=None):
        """The glTF document; background is the uniform environment radiance."""
        scene = {"name": self.name,
                 "nodes": [i for i in range(len(self.nodes))
                           if i not in self.children]}
        if background is not None:
            scene["extras"] = {"background": background}
        extensions = {e for m in self.materials for e in m.get("extensions", {})}
        if self.lights:
            extensions.add("KHR_lights_punctual")
        document = {
            "asset": {"version": "2.0", "generator": generator},
            "extensionsUsed": sorted(extensions),
            "scene": 0,
            "scenes": [scene],
            "nodes": self.nodes,
            "cameras": self.cameras,
            "meshes": self.meshes,
            "materials": self.materials,
        }
        if self.lights:
            document["extensions"] = {
                "KHR_lights_punctual": {"lights": self.lights}}
        data = bytes(self.data)
        document.update({
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [{"byteLength": len(data),
                         "uri": "data:application/octet-stream;base64,"
                                + base64.b64encode(data).decode("ascii")}],
        })
        return document


def write_gltf(path, document):
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(json.dumps(document, indent=1) + "\n")
