#!/usr/bin/env python3
"""Generate the hard-case scenes in scenes/hard/: scenes that have broken
renderers before. What each one stresses is in its glTF `extras.stresses`
and in scenes/README.md; tests/HardCasesTest.cpp renders every one.

    python3 scripts/make_hard_scenes.py            # writes every scene
    python3 scripts/make_hard_scenes.py -d /tmp    # elsewhere

Only the Python standard library is used and the output is deterministic.
"""

import argparse
import math
import os

from make_scenes import GENERATOR, GLASS, MIRROR, WHITE, cornell_box
from scenelib import (SceneBuilder, diffuse, emitter, glass, look_rotation,
                      metal, quad, uv_sphere, write_gltf)

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scaled_cornell_box(name, scale=1.0, translation=(0.0, 0.0, 0.0)):
    """The Cornell box (area light, mirror and glass spheres, camera) under
    one root node that scales and moves all of it. Radiance does not depend
    on scale, so every such box renders the image of the unit box."""
    scene = cornell_box(name)
    roots = [i for i in range(len(scene.nodes)) if i not in scene.children]
    scene.add_node("root", scale=[scale] * 3, translation=list(translation),
                   children=roots)
    return scene


def document(scene, stresses, background=None):
    doc = scene.gltf(GENERATOR, background=background)
    doc["scenes"][0]["extras"] = dict(doc["scenes"][0].get("extras", {}),
                                      stresses=stresses)
    return doc


def scale_tiny():
    return document(scaled_cornell_box("scale_tiny", scale=1e-4),
                    "the Cornell box at 1e-4 units: ray offsets and "
                    "intersection epsilons that do not scale leak or "
                    "self-shadow")


def scale_huge():
    return document(scaled_cornell_box("scale_huge", scale=1e5),
                    "the Cornell box at 1e5 units: absolute epsilons become "
                    "too small against the coordinates' rounding")


def far_from_origin():
    return document(scaled_cornell_box("far_from_origin",
                                       translation=(1e5, 1e5, 1e5)),
                    "the unit Cornell box 1e5 units from the origin: "
                    "positions carry only ~1e-2 of absolute precision")


def closed_box():
    """A closed cube of shared-edge triangles with the camera inside; every
    light is outside. Anything but black inside is a leak."""
    scene = SceneBuilder("closed_box")
    h = 1.0
    faces = [((-h, -h, -h), (2 * h, 0, 0), (0, 2 * h, 0)),    # z = -h
             ((-h, -h, h), (0, 2 * h, 0), (2 * h, 0, 0)),     # z = +h
             ((-h, -h, -h), (0, 2 * h, 0), (0, 0, 2 * h)),    # x = -h
             ((h, -h, -h), (0, 0, 2 * h), (0, 2 * h, 0)),     # x = +h
             ((-h, -h, -h), (0, 0, 2 * h), (2 * h, 0, 0)),    # y = -h
             ((-h, h, -h), (2 * h, 0, 0), (0, 0, 2 * h))]     # y = +h
    # One mesh with shared vertices, so edges are hit exactly by the
    # watertight test from both triangles that share them.
    positions, index_of, indices = [], {}, []
    for origin, u, v in faces:
        quad_positions, _, quad_indices = quad(origin, u, v)
        for i in quad_indices:
            p = quad_positions[i]
            if p not in index_of:
                index_of[p] = len(positions)
                positions.append(p)
            indices.append(index_of[p])
    normals = [tuple(c / math.sqrt(3) for c in p) for p in positions]
    scene.add_mesh("box", (positions, normals, indices), WHITE)
    # A mirror and a glass sphere inside: specular paths cannot let light in
    # either. (They also give the box the lobes of light-transport.gltf, so
    # the tests build one program per algorithm for both scenes.)
    sphere = scene.add_geometry(*uv_sphere())
    scene.add_mesh("mirror_sphere", sphere, MIRROR,
                   translation=[0.5, 0.5, 0.5], scale=[0.2] * 3)
    scene.add_mesh("glass_sphere", sphere, GLASS,
                   translation=[0.5, -0.6, 0.4], scale=[0.2] * 3)
    scene.add_mesh("outside_light", quad((-2, 3, -2), (4, 0, 0), (0, 0, 4)),
                   emitter("outside_light", [1, 1, 1], 50.0))
    scene.add_light("outside_point", "point", [1, 1, 1], 100.0,
                    translation=[0.0, -3.0, 0.0])
    # Looking at a corner, where three edges and a vertex meet.
    scene.add_camera(1.4, 1.0, translation=[-0.2, -0.2, -0.2],
                     rotation=look_rotation((-1.0, -0.8, -1.0)))
    return document(scene, "a closed box of shared-edge triangles, camera "
                           "inside with a mirror and a glass sphere, lights "
                           "outside: must render black",
                    background=[1.0, 1.0, 1.0])


def degenerate_geometry():
    """The Cornell box with zero-area, needle and coincident triangles, and
    the camera grazing the floor."""
    scene = cornell_box("degenerate_geometry")
    zero_area = ([(0, 0.5, 0), (0.5, 0.5, 0), (1, 0.5, 0),       # collinear
                  (0.2, 0.8, 0.1), (0.2, 0.8, 0.1), (0.3, 0.9, 0.1)],  # repeated
                 [(0, 1, 0)] * 6, [0, 1, 2, 3, 4, 5])
    scene.add_mesh("zero_area", zero_area, WHITE)
    needle = ([(-0.9, 0.05, -0.5), (0.9, 0.05, -0.5), (0.9, 0.0500001, -0.5)],
              [(0, 0, 1)] * 3, [0, 1, 2])
    scene.add_mesh("needle", needle, MIRROR)
    # A coincident quad on the floor, another material: z-fighting.
    scene.add_mesh("coincident", quad((-0.6, 0, -0.6), (0, 0, 1.2), (1.2, 0, 0)),
                   diffuse("blue", [0.1, 0.2, 0.7, 1.0]))
    doc = document(scene, "zero-area and needle triangles, a face coincident "
                          "with the floor (z-fighting), a camera whose rays "
                          "graze the floor")
    camera_node = next(n for n in doc["nodes"] if n["name"] == "camera")
    camera_node["translation"] = [0.0, 0.002, 0.95]
    return doc


def light_transport():
    """Lights and materials at their limits, in the Cornell box, with a dim
    background through its open side (a light at infinity as well)."""
    scene = cornell_box("light_transport", without={"light"})
    sphere = scene.add_geometry(*uv_sphere())
    # A light inside a glass sphere (only caustic paths leave it) and a point
    # light a hair above the floor.
    scene.add_mesh("light_glass", sphere, GLASS, translation=[0.0, 1.3, 0.0],
                   scale=[0.25] * 3)
    scene.add_light("light_in_glass", "point", [1, 0.9, 0.8], 1.0,
                    translation=[0.0, 1.3, 0.0])
    scene.add_light("point_on_floor", "point", [1, 1, 1], 0.05,
                    translation=[0.6, 1e-5, -0.6])
    # A tiny, very bright emitter (1 mm square, radiance 1e6).
    scene.add_mesh("tiny_light", quad((-0.0005, 1.99, -0.0005), (0.001, 0, 0),
                                      (0, 0, 0.001)),
                   emitter("tiny_light", [1, 1, 1], 1e6))
    # Glass of IOR 1.0 and 2.4; metals of roughness 0 and 1e-4 and rough
    # glass of roughness 1e-4.
    objects = [("ior_1", glass("ior_1", 1.0), [-0.6, 1.2, 0.2]),
               ("ior_2_4", glass("ior_2_4", 2.4), [0.6, 1.2, 0.2]),
               ("roughness_0", metal("roughness_0", [0.9, 0.9, 0.9, 1], 0.0),
                [-0.6, 0.2, 0.6]),
               ("roughness_1e-4", metal("roughness_1e-4", [0.9, 0.9, 0.9, 1],
                                        1e-4), [0.0, 0.2, 0.6])]
    rough_glass = glass("rough_glass_1e-4")
    rough_glass["pbrMetallicRoughness"]["roughnessFactor"] = 1e-4
    objects.append(("rough_glass_1e-4", rough_glass, [0.6, 0.2, 0.6]))
    for name, material, translation in objects:
        scene.add_mesh(name, sphere, material, translation=translation,
                       scale=[0.15] * 3)
    # Shading normals pointing against the geometric normal.
    positions, normals, indices = uv_sphere()
    flipped = [tuple(-c for c in n) for n in normals]
    scene.add_mesh("flipped_normals", (positions, flipped, indices), WHITE,
                   translation=[0.0, 0.7, -0.6], scale=[0.2] * 3)
    # Two facing mirrors: specular chains far longer than the path length.
    scene.add_mesh("mirror_a", quad((-0.99, 0.5, -0.9), (0, 0, 0.6), (0, 0.6, 0)),
                   MIRROR)
    scene.add_mesh("mirror_b", quad((0.99, 0.5, -0.9), (0, 0.6, 0), (0, 0, 0.6)),
                   MIRROR)
    return document(scene, "a point light inside a glass sphere and one 1e-5 "
                           "above the floor, a 1 mm light of radiance 1e6, "
                           "glass of IOR 1.0 and 2.4, roughness 0 and 1e-4, "
                           "shading normals against the geometric normal, "
                           "facing mirrors (specular chains past the path "
                           "length), a dim background through the open side",
                    background=[0.05, 0.05, 0.05])


SCENES = {
    "scale-tiny": scale_tiny,
    "scale-huge": scale_huge,
    "far-from-origin": far_from_origin,
    "closed-box": closed_box,
    "degenerate-geometry": degenerate_geometry,
    "light-transport": light_transport,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-d", "--directory",
                        default=os.path.join(REPO_ROOT, "scenes", "hard"))
    args = parser.parse_args()
    os.makedirs(args.directory, exist_ok=True)
    for name, make in SCENES.items():
        write_gltf(os.path.join(args.directory, name + ".gltf"), make())


if __name__ == "__main__":
    main()
