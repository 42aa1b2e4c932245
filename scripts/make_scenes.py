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
- smallvcm-area, smallvcm-point: the Cornell boxes of SmallVCM (the VCM
  paper's scalar CPU reference), for scripts/compare_smallvcm.sh: its scene 1
  (a large mirror sphere under the ceiling's light box) and its scene 2 (a
  mirror and a glass sphere under a point light), converted from its z-up
  frame, with its floor's diffuse 0.1 + Phong 0.7 (exponent 90) as a GGX
  metal blend and its analytic spheres tessellated.

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


# SmallVCM's Cornell box (scene.hxx, LoadCornellBox), from its frame (z up,
# the camera looking along +y) into glTF's (y up): (x, y, z) -> (x, z, -y).
def from_smallvcm(p):
    return (p[0], p[2], -p[1])


SMALLVCM_BOX = ((-1.27029, -1.25549, -1.28002), (1.28975, 1.30455, 1.28002))


def smallvcm_box(name, spheres, with_light_box):
    """The box (open at the front), its spheres (centre, radius, material,
    in SmallVCM's frame) and its camera; with the 0.5 x 0.5 x 0.02 light box
    under the ceiling, whose bottom face emits."""
    (x0, y0, z0), (x1, y1, z1) = SMALLVCM_BOX
    white = diffuse("white", [0.803922, 0.803922, 0.803922, 1.0])
    # Diffuse 0.1 + a glossy lobe of 0.7: a metal blend of base 0.8 and
    # metallic 0.875 (0.125 x 0.8 diffuse, 0.875 x 0.8 metal); Phong's
    # exponent n = 90 as a microfacet alpha sqrt(2 / (n + 2)) = 0.147,
    # roughness sqrt(alpha).
    floor = {"name": "glossy_floor",
             "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                      "metallicFactor": 0.875,
                                      "roughnessFactor": 0.384}}
    # (name, material, origin, u, v) in SmallVCM's frame; cross(u, v) faces
    # the room.
    walls = [
        ("floor", floor, (x0, y0, z0), (x1 - x0, 0, 0), (0, y1 - y0, 0)),
        ("ceiling", white, (x0, y0, z1), (0, y1 - y0, 0), (x1 - x0, 0, 0)),
        ("back_wall", diffuse("blue", [0.156863, 0.172549, 0.803922, 1.0]),
         (x0, y1, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0)),
        ("left_wall", diffuse("green", [0.156863, 0.803922, 0.172549, 1.0]),
         (x0, y0, z0), (0, y1 - y0, 0), (0, 0, z1 - z0)),
        ("right_wall", diffuse("red", [0.803922, 0.152941, 0.152941, 1.0]),
         (x1, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0)),
    ]
    if with_light_box:
        b0, b1, top = 1.26002, 1.28002, 0.5
        light = emitter("light", [1.0, 1.0, 1.0], 25.03329895614464)
        walls += [
            ("light", light, (-0.25, -0.25, b0), (0, top, 0), (top, 0, 0)),
            ("light_box_front", white, (-0.25, -0.25, b0), (top, 0, 0), (0, 0, b1 - b0)),
            ("light_box_back", white, (-0.25, 0.25, b0), (0, 0, b1 - b0), (top, 0, 0)),
            ("light_box_left", white, (-0.25, -0.25, b0), (0, 0, b1 - b0), (0, top, 0)),
            ("light_box_right", white, (0.25, -0.25, b0), (0, top, 0), (0, 0, b1 - b0)),
        ]
    scene = SceneBuilder(name)
    for wall, material, origin, u, v in walls:
        scene.add_mesh(wall, quad(from_smallvcm(origin), from_smallvcm(u),
                                  from_smallvcm(v)), material)
    sphere = scene.add_geometry(*uv_sphere(128, 64))
    for sphere_name, centre, radius, material in spheres:
        scene.add_mesh(sphere_name, sphere, material,
                       translation=list(from_smallvcm(centre)),
                       scale=[radius] * 3)
    # Horizontal field of view 45 degrees, square image.
    scene.add_camera(math.radians(45.0), 1.0,
                     translation=list(from_smallvcm((-0.0439815, -4.12529, 0.222539))),
                     rotation=look_rotation(from_smallvcm((0.00688625, 0.998505, -0.0542161)),
                                            from_smallvcm((3.73896e-4, 0.0542148, 0.998529))))
    return scene


def smallvcm_area():
    mirror = metal("mirror", [1.0, 1.0, 1.0, 1.0], 0.0)
    return smallvcm_box("smallvcm_area", [("mirror_sphere", (0.00973, 0.02453, -0.48002), 0.8, mirror)],
                        with_light_box=True).gltf(GENERATOR)


def smallvcm_point():
    mirror = metal("mirror", [1.0, 1.0, 1.0, 1.0], 0.0)
    spheres = [("mirror_sphere", (-0.53885, 0.02453, -0.78002), 0.5, mirror),
               ("glass_sphere", (0.55831, 0.02453, -0.78002), 0.5, glass("glass", 1.6))]
    scene = smallvcm_box("smallvcm_point", spheres, with_light_box=False)
    # 70 W: 70 / (4 pi) W/sr.
    scene.add_light("point_light", "point", [1.0, 1.0, 1.0], 70.0 / (4.0 * math.pi),
                    translation=list(from_smallvcm((0.0, -0.5, 1.0))))
    return scene.gltf(GENERATOR)


BENCH_SCENES = {
    "cornell-box-130k": cornell_box_130k,
    "displaced-1m": displaced_1m,
    "smallvcm-area": smallvcm_area,
    "smallvcm-point": smallvcm_point,
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
