"""wavevcm `pt` against Mitsuba 3's `path` integrator on the same scene, for
the same wall time, on the same machine (issue 12's bar for path tracing).

Run through scripts/compare_mitsuba.sh, which makes the Python environment
(Mitsuba 3 from PyPI, its llvm_ad_rgb variant on Debian's libLLVM 19).

The glTF scene is converted here for Mitsuba: world-space PLY meshes with the
vertex normals, and for each material the Mitsuba BSDF of the same model
(Lambert walls -> diffuse, a smooth metal -> conductor, smooth transmission
-> dielectric, emission -> area emitter). Only what such a Cornell box uses
is converted; anything else is refused by name.

Each renderer's equal-time image is measured against its own long
reference, so the two are compared on how fast they converge, not on where
(their models differ in details, such as Mitsuba's conductor having no
Fresnel term where glTF's metal has Schlick's). The relMSE between the two
references is printed as a check that both render the same scene.
"""

import argparse
import base64
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

from comparelib import machine, relmse


# --- glTF -> world-space triangles -------------------------------------------

COMPONENT_DTYPE = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
TYPE_SIZE = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def load_buffers(gltf, base):
    out = []
    for b in gltf["buffers"]:
        uri = b["uri"]
        if uri.startswith("data:"):
            out.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(base, uri), "rb") as f:
                out.append(f.read())
    return out


def accessor(gltf, buffers, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    dtype = np.dtype(COMPONENT_DTYPE[a["componentType"]])
    width = TYPE_SIZE[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = view.get("byteStride", dtype.itemsize * width)
    raw = np.frombuffer(buffers[view["buffer"]], dtype=np.uint8, count=stride * (a["count"] - 1) + dtype.itemsize * width,
                        offset=start)
    rows = np.lib.stride_tricks.as_strided(raw, shape=(a["count"], dtype.itemsize * width), strides=(stride, 1))
    return np.ascontiguousarray(rows).view(dtype).reshape(a["count"], width)


def node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.eye(4)
    t[:3, 3] = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.eye(4)
    r[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    s = np.diag(node.get("scale", [1, 1, 1]) + [1])
    return t @ r @ s


def world_nodes(gltf):
    """(node, world matrix) for every node of the default scene."""
    scene = gltf["scenes"][gltf.get("scene", 0)]
    stack = [(i, np.eye(4)) for i in scene["nodes"]]
    while stack:
        i, parent = stack.pop()
        node = gltf["nodes"][i]
        m = parent @ node_matrix(node)
        yield node, m
        stack.extend((c, m) for c in node.get("children", []))


def write_ply(path, positions, normals, faces):
    """normals: None for a flat-shaded mesh (no vertex normals, as in glTF)."""
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
              "property float x\nproperty float y\nproperty float z\n" % len(positions) +
              ("property float nx\nproperty float ny\nproperty float nz\n" if normals is not None else "") +
              "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
    vertices = (positions if normals is None else np.hstack([positions, normals])).astype("<f4")
    face_rows = np.zeros(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
    face_rows["n"] = 3
    face_rows["v"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.tobytes())
        f.write(face_rows.tobytes())


def mitsuba_bsdf(material, name):
    pbr = material.get("pbrMetallicRoughness", {})
    ext = material.get("extensions", {})
    base = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
    metallic = pbr.get("metallicFactor", 1.0)
    roughness = pbr.get("roughnessFactor", 1.0)
    transmission = ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0)
    specular = ext.get("KHR_materials_specular", {}).get("specularFactor", 1.0)
    if transmission == 1.0 and roughness == 0.0 and metallic == 0.0:
        return {"type": "dielectric", "int_ior": ext.get("KHR_materials_ior", {}).get("ior", 1.5), "ext_ior": 1.0}
    if metallic == 1.0 and roughness == 0.0:
        return {"type": "conductor", "material": "none", "specular_reflectance": {"type": "rgb", "value": base}}
    if metallic == 0.0 and specular == 0.0 and transmission == 0.0:
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": base}}
    sys.exit("compare_mitsuba: material '%s' has no Mitsuba counterpart in this script "
             "(supported: Lambert with specularFactor 0, smooth metal, smooth glass)" % name)


def mitsuba_scene(path, width, height, max_depth, mesh_dir):
    try:
        with open(path) as f:
            gltf = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit("compare_mitsuba: %s: cannot read it as glTF JSON (%s)" % (path, e))
    buffers = load_buffers(gltf, os.path.dirname(path))
    os.makedirs(mesh_dir, exist_ok=True)
    scene = {"type": "scene", "integrator": {"type": "path", "max_depth": max_depth}}
    camera = None
    for node, m in world_nodes(gltf):
        if "camera" in node and camera is None:
            camera = (gltf["cameras"][node["camera"]], m)
        if "mesh" not in node:
            continue
        normal_matrix = np.linalg.inv(m[:3, :3]).T
        for k, prim in enumerate(gltf["meshes"][node["mesh"]]["primitives"]):
            if prim.get("mode", 4) != 4:
                sys.exit("compare_mitsuba: %s: mesh %d has a primitive that is not a triangle list, "
                         "which this converter does not handle" % (path, node["mesh"]))
            p = accessor(gltf, buffers, prim["attributes"]["POSITION"]).astype(np.float64)
            if "indices" in prim:
                idx = accessor(gltf, buffers, prim["indices"]).reshape(-1, 3).astype(np.int32)
            else:
                idx = np.arange(len(p), dtype=np.int32).reshape(-1, 3)
            p = p @ m[:3, :3].T + m[:3, 3]
            n = None
            if "NORMAL" in prim["attributes"]:
                n = accessor(gltf, buffers, prim["attributes"]["NORMAL"]).astype(np.float64) @ normal_matrix.T
                n /= np.linalg.norm(n, axis=1, keepdims=True)
            name = "shape%d_%s_%d" % (len(scene), node.get("name", "mesh"), k)  # unique, names may repeat
            ply = os.path.join(mesh_dir, name + ".ply")
            write_ply(ply, p, n, idx)
            if "material" not in prim:
                sys.exit("compare_mitsuba: %s: a primitive of mesh %d has no material (glTF's default, "
                         "a rough white metal, has no Mitsuba counterpart here)" % (path, node["mesh"]))
            material = gltf["materials"][prim["material"]]
            shape = {"type": "ply", "filename": ply, "bsdf": mitsuba_bsdf(material, material.get("name", "?"))}
            emissive = material.get("emissiveFactor", [0, 0, 0])
            strength = material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
            if max(emissive) > 0:
                shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": [e * strength for e in emissive]}}
            scene[name] = shape
    if camera is None:
        sys.exit("compare_mitsuba: the scene has no camera")
    cam, m = camera
    origin = m[:3, 3]
    forward = m[:3, :3] @ [0, 0, -1]
    up = m[:3, :3] @ [0, 1, 0]
    import mitsuba as mi
    scene["sensor"] = {
        "type": "perspective", "fov_axis": "y", "fov": math.degrees(cam["perspective"]["yfov"]),
        "to_world": mi.ScalarTransform4f().look_at(origin=origin.tolist(), target=(origin + forward).tolist(),
                                                   up=up.tolist()),
        "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
        "sampler": {"type": "independent"},
    }
    return scene


# --- rendering for a wall time -----------------------------------------------

def render_mitsuba(scene, seconds, out, spp_per_pass, seed):
    """Passes of spp_per_pass samples per pixel, with seeds seed, seed + 1,
    ..., until `seconds` have passed (after one untimed pass: Dr.Jit compiles
    the kernel at the first)."""
    import drjit as dr
    import mitsuba as mi
    dr.eval(mi.render(scene, spp=spp_per_pass, seed=seed))
    total, passes = None, 0
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        image = mi.render(scene, spp=spp_per_pass, seed=seed + passes)
        total = image if total is None else total + image
        dr.eval(total)
        passes += 1
    elapsed = time.perf_counter() - start
    mi.Bitmap(total / passes).write(out)
    return passes * spp_per_pass, elapsed


def render_wavevcm(binary, scene, seconds, out, width, height, max_depth, seed):
    stats = out + ".json"
    subprocess.run([binary, "render", scene, "-a", "pt", "-t", str(seconds), "--width", str(width), "--height",
                    str(height), "--max-path-length", str(max_depth), "--seed", str(seed), "-q", "-o", out,
                    "--stats", stats], check=True)
    with open(stats) as f:
        s = json.load(f)
    return s["iterations"], s["render_seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="scenes/cornell-box.gltf")
    ap.add_argument("--seconds", type=float, default=30.0, help="wall time of each equal-time render")
    ap.add_argument("--reference-seconds", type=float, default=240.0, help="wall time of each renderer's reference")
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--height", type=int, default=512)
    ap.add_argument("--max-depth", type=int, default=10, help="segments, the camera's included (both renderers)")
    ap.add_argument("--spp-per-pass", type=int, default=16, help="Mitsuba's samples per pixel per render call")
    ap.add_argument("--wavevcm", default="build/wavevcm")
    ap.add_argument("--out", default="build/mitsuba-compare")
    args = ap.parse_args()

    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    os.makedirs(args.out, exist_ok=True)
    scene = mi.load_dict(mitsuba_scene(args.scene, args.width, args.height, args.max_depth,
                                       os.path.join(args.out, "meshes")))
    o = lambda name: os.path.join(args.out, name)
    rows = []
    for label, render in (
            ("Mitsuba 3 path (llvm_ad_rgb)",
             lambda t, out, seed: render_mitsuba(scene, t, out, args.spp_per_pass, seed)),
            ("wavevcm pt",
             lambda t, out, seed: render_wavevcm(args.wavevcm, args.scene, t, out, args.width, args.height,
                                                 args.max_depth, seed))):
        key = "mitsuba" if label.startswith("Mitsuba") else "wavevcm"
        print("compare_mitsuba: %s, reference (%g s)" % (label, args.reference_seconds), file=sys.stderr)
        # Different seeds: an image correlated with its reference would look closer to it.
        render(args.reference_seconds, o(key + "-reference.exr"), 1 << 20)
        print("compare_mitsuba: %s, equal time (%g s)" % (label, args.seconds), file=sys.stderr)
        spp, seconds = render(args.seconds, o(key + ".exr"), 1)
        rows.append((label, key, spp, seconds))

    pixels = args.width * args.height
    print("machine: %s\n" % machine())
    print("| renderer | spp in %g s | samples/s | relMSE vs own %g s reference |" % (args.seconds, args.reference_seconds))
    print("| --- | --- | --- | --- |")
    errors = {}
    for label, key, spp, seconds in rows:
        errors[key] = relmse(args.wavevcm, o(key + ".exr"), o(key + "-reference.exr"))
        rates = spp * pixels / seconds
        print("| %s | %d | %.3g M | %.4g |" % (label, spp, rates / 1e6, errors[key]))
    rate = {key: spp / seconds for _, key, spp, seconds in rows}
    print("\nwavevcm / Mitsuba: samples/s %.2fx, relMSE at equal time %.2fx" %
          (rate["wavevcm"] / rate["mitsuba"], errors["wavevcm"] / errors["mitsuba"]))
    print("relMSE between the two references (same scene check): %.4g" %
          relmse(args.wavevcm, o("wavevcm-reference.exr"), o("mitsuba-reference.exr")))


if __name__ == "__main__":
    main()
