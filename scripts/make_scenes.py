#!/usr/bin/env python3
"""Generate wavevcm's test scenes in scenes/.

Each scene is a single self-contained glTF 2.0 file (buffer embedded as a
base64 data URI); what each one tests is listed in scenes/README.md.

- cornell-box: the classic Cornell box (interior x in [-1, 1], y in [0, 2],
  z in [-1, 1], open towards +Z) with white floor, ceiling and back wall, a red
  left wall, a green right wall, a small downward-facing area light just below
  the ceiling, a mirror sphere and a glass sphere, plus a perspective camera.
  It exercises TRS and matrix node transforms, a node hierarchy, shared
  accessors and several KHR_materials_* extensions.
- cornell-box-point: the box lit by a point light of the area light's power.
- cornell-box-background: the box without ceiling or area light, lit by a
  uniform white background through the open top and front.
- cornell-box-directional: the box without the red wall or area light, lit by
  a directional light slanting in through the open side.
- caustics: a glass Stanford bunny and a gold Utah teapot on a large floor,
  lit by a tiny, very bright emissive square (meshes from scenes/assets/).

Benchmark scenes, written only when named (too large to keep in the tree;
scripts/bench_tables.sh writes them into the build directory):

- cornell-box-130k: the Cornell box with each sphere tessellated into 65K
  triangles (130K in all).
- displaced-1m: the Cornell box around a displaced sphere of 1M triangles
  (bumps of 5 % of the radius), lit by the area light.

Usage (from the repository root):

    python3 scripts/make_scenes.py                  # writes every scene
    python3 scripts/make_scenes.py caustics -d /tmp # one scene, elsewhere
    python3 scripts/make_scenes.py displaced-1m -d build/bench-scenes

Only the Python standard library is used and the output is deterministic.
"""

import argparse
import math
import os

from scenelib import (SceneBuilder, diffuse, emitter, glass, look_rotation,
                      metal, outward, panel, quad, read_obj, rotation_y,
                      smooth_normals, stand_on_floor, sub, uv_sphere,
                      write_gltf)

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GENERATOR = "wavevcm scripts/make_scenes.py"

WHITE = diffuse("white", [0.725, 0.71, 0.68, 1.0])
RED = diffuse("red", [0.63, 0.065, 0.05, 1.0])
GREEN = diffuse("green", [0.14, 0.45, 0.091, 1.0])
MIRROR = metal("mirror", [0.95, 0.95, 0.95, 1.0], 0.0)
GLASS = glass("glass")

# The Cornell box's area light: radiance 40 x (1, 0.85, 0.6) over 0.5 x 0.4 m.
LIGHT_COLOR = [1.0, 0.85, 0.6]
LIGHT_RADIANCE = 40.0
LIGHT_AREA = 0.5 * 0.4

# (name, material, origin, u, v): the normal cross(u, v) faces the interior.
BOX_QUADS = [
    ("floor", WHITE, (-1, 0, -1), (0, 0, 2), (2, 0, 0)),
    ("ceiling", WHITE, (-1, 2, -1), (2, 0, 0), (0, 0, 2)),
    ("back_wall", WHITE, (-1, 0, -1), (2, 0, 0), (0, 2, 0)),
    ("left_wall", RED, (-1, 0, -1), (0, 2, 0), (0, 0, 2)),
    ("right_wall", GREEN, (1, 0, -1), (0, 0, 2), (0, 2, 0)),
    ("light", emitter("light", LIGHT_COLOR, LIGHT_RADIANCE),
     (-0.25, 1.98, -0.2), (0.5, 0, 0), (0, 0, 0.4)),
]


def cornell_box(name, without=(), sphere_segments=32, with_spheres=True):
    """The box, its spheres and its camera, minus the quads named in without."""
    scene = SceneBuilder(name)
    for quad_name, material, origin, u, v in BOX_QUADS:
        if quad_name not in without:
            scene.add_mesh(quad_name, quad(origin, u, v), material)
    if with_spheres:
        add_spheres(scene, sphere_segments)
    scene.add_camera(0.68, 1.0, translation=[0.0, 1.0, 3.9])
    return scene


def add_spheres(scene, sphere_segments):
    """The box's mirror and glass spheres."""
    sphere = scene.add_geometry(*uv_sphere(sphere_segments,
                                           sphere_segments // 2))
    spheres = [("mirror_sphere", MIRROR, [-0.45, 0.4, -0.3], 0.4),
               ("glass_sphere", GLASS, [0.5, 0.35, 0.35], 0.35)]
    sphere_nodes = [scene.add_mesh(sphere_name, sphere, material,
                                   translation=translation,
                                   scale=[radius] * 3)
                    for sphere_name, material, translation, radius in spheres]
    identity = [1.0 if row == col else 0.0
                for col in range(4) for row in range(4)]
    scene.add_node("objects", matrix=identity, children=sphere_nodes)


def cornell_box_default():
    return cornell_box("cornell_box").gltf(GENERATOR)


def cornell_box_point():
    # A point light of the area light's power pi L A has intensity
    # pi L A / (4 pi) = L A / 4 (2 W/sr per unit of LIGHT_COLOR).
    scene = cornell_box("cornell_box_point", without={"light"})
    scene.add_light("point_light", "point", LIGHT_COLOR,
                    LIGHT_RADIANCE * LIGHT_AREA / 4,
                    translation=[0.0, 1.8, 0.0])
    return scene.gltf(GENERATOR)


def cornell_box_background():
    scene = cornell_box("cornell_box_background",
                        without={"light", "ceiling"})
    return scene.gltf(GENERATOR, background=[1.0, 1.0, 1.0])


def cornell_box_directional():
    scene = cornell_box("cornell_box_directional",
                        without={"light", "left_wall"})
    # Sunlight through the open left side, travelling right, down and back.
    scene.add_light("sun", "directional", [1.0, 1.0, 1.0], 3.0,
                    rotation=look_rotation((1.0, -0.6, -0.3)))
    return scene.gltf(GENERATOR)


def caustics():
    scene = SceneBuilder("caustics")
    scene.add_mesh("floor", quad((-6, 0, -6), (0, 0, 12), (12, 0, 0)),
                   diffuse("floor", [0.75, 0.75, 0.75, 1.0]))

    # (mesh, material, where it stands, turn about +Y in degrees); each is
    # scaled to 0.5 m tall.
    assets = os.path.join(REPO_ROOT, "scenes", "assets")
    objects = [("bunny", GLASS, [-0.5, 0.0, 0.15], 20.0),
               ("teapot", metal("gold", [1.0, 0.78, 0.34, 1.0], 0.15),
                [0.45, 0.0, -0.25], -35.0)]
    for name, material, translation, turn in objects:
        positions, indices = read_obj(os.path.join(assets, name + ".obj"))
        positions = stand_on_floor(positions, 0.5)
        indices = outward(positions, indices)
        scene.add_mesh(name, (positions, smooth_normals(positions, indices),
                              indices),
                       material, translation=translation,
                       rotation=rotation_y(turn))

    # A 5 cm square above, behind and to the left, aimed at the objects: the
    # bunny's caustic falls on the floor in front of it, towards the camera.
    light_position, target = (-1.0, 1.8, -1.2), (0.0, 0.1, 0.0)
    scene.add_mesh("light", panel(0.05, 0.05),
                   emitter("light", [1.0, 0.9, 0.75], 9000.0),
                   translation=list(light_position),
                   rotation=look_rotation(sub(target, light_position)))

    camera_position = (0.0, 1.0, 2.0)
    scene.add_camera(0.6, 16 / 9, translation=list(camera_position),
                     rotation=look_rotation(sub((0.0, 0.12, 0.0),
                                                camera_position)))
    return scene.gltf(GENERATOR, background=[0.02, 0.02, 0.02])


def cornell_box_130k():
    # 256 segments x 128 rings: 2 x 256 x 127 = 65,024 triangles per sphere.
    return cornell_box("cornell_box_130k", sphere_segments=256).gltf(GENERATOR)


def displaced_1m():
    # 1024 x 512: 2 x 1024 x 511 = 1,046,528 triangles.
    positions, _, indices = uv_sphere(1024, 512)
    bumped = []
    for x, y, z in positions:
        theta, phi = math.acos(max(-1.0, min(1.0, y))), math.atan2(z, x)
        r = 1.0 + 0.05 * math.sin(24 * theta) * math.sin(24 * phi)
        bumped.append((x * r, y * r, z * r))
    scene = cornell_box("displaced_1m", with_spheres=False)
    scene.add_mesh("displaced_sphere",
                   (bumped, smooth_normals(bumped, indices), indices),
                   diffuse("clay", [0.8, 0.6, 0.45, 1.0]),
                   translation=[0.0, 0.75, 0.0], scale=[0.7] * 3)
    return scene.gltf(GENERATOR)


BENCH_SCENES = {
    "cornell-box-130k": cornell_box_130k,
    "displaced-1m": displaced_1m,
}

SCENES = {
    "cornell-box": cornell_box_default,
    "cornell-box-point": cornell_box_point,
    "cornell-box-background": cornell_box_background,
    "cornell-box-directional": cornell_box_directional,
    "caustics": caustics,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="scenes to write (default: all of %s; also %s)"
                             % (", ".join(SCENES), ", ".join(BENCH_SCENES)))
    parser.add_argument("-d", "--directory",
                        default=os.path.join(REPO_ROOT, "scenes"),
                        help="output directory (default: %(default)s)")
    args = parser.parse_args()
    every = dict(SCENES, **BENCH_SCENES)
    unknown = [name for name in args.scenes if name not in every]
    if unknown:
        parser.error("unknown scene: " + ", ".join(unknown))
    os.makedirs(args.directory, exist_ok=True)
    for name in args.scenes or SCENES:
        write_gltf(os.path.join(args.directory, name + ".gltf"),
                   every[name]())


if __name__ == "__main__":
    main()
