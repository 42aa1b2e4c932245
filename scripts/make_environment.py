#!/usr/bin/env python3
"""Writes scenes/environments/sky.pfm: a small equirectangular sky for
`wavevcm render --environment` (row 0 looks straight up, the centre column
along -z; kernels/lights/environment.h): a blue sky brighter towards the
horizon, a grey-brown ground, and a sun of radiance 500 and half-angle
about 1.4 degrees at 35 degrees elevation, 40 degrees left of -z.

  scripts/make_environment.py [--width 256] [--sun-radiance 500] [OUTPUT]

(scripts/make_textured_scene.py writes a sunnier one with write_sky.)

Standard library only (PFM: little-endian float32 rows, bottom row first).
"""
import argparse
import math
import os
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def radiance(theta, phi, sun, sun_radiance=500.0):
    """Linear RGB radiance of direction (theta from +y, phi = atan2(x, -z))."""
    d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
    if math.cos(theta) > 0:
        t = 1 - math.cos(theta)  # 0 at the zenith, 1 at the horizon
        c = (0.12 + 0.22 * t, 0.22 + 0.2 * t, 0.48 + 0.1 * t)
    else:
        c = (0.09, 0.075, 0.06)
    cos_sun = sum(a * b for a, b in zip(d, sun))
    if cos_sun > math.cos(math.radians(1.4)):
        c = (sun_radiance, 0.95 * sun_radiance, 0.85 * sun_radiance)
    return c


def write_sky(output, w, sun_radiance=500.0):
    """Writes the sky as a PFM of w x w/2 texels."""
    h = w // 2
    elevation, azimuth = math.radians(35), math.radians(-40)
    sun = (math.cos(elevation) * math.sin(azimuth), math.sin(elevation), -math.cos(elevation) * math.cos(azimuth))
    rows = []
    for y in range(h):
        row = []
        for x in range(w):
            # the texel's radiance: the mean of 4 x 4 directions in it
            acc = [0.0, 0.0, 0.0]
            for sy in range(4):
                for sx in range(4):
                    theta = math.pi * (y + (sy + 0.5) / 4) / h
                    phi = 2 * math.pi * ((x + (sx + 0.5) / 4) / w - 0.5)
                    c = radiance(theta, phi, sun, sun_radiance)
                    acc = [s + v / 16 for s, v in zip(acc, c)]
            row.extend(acc)
        rows.append(row)
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    with open(output, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        for row in reversed(rows):  # PFM stores the bottom row first
            f.write(struct.pack("<%df" % len(row), *row))
    print("wrote", output, w, "x", h)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--sun-radiance", type=float, default=500.0)
    p.add_argument("output", nargs="?", default=os.path.join(ROOT, "scenes", "environments", "sky.pfm"))
    a = p.parse_args()
    write_sky(a.output, a.width, a.sun_radiance)


if __name__ == "__main__":
    main()
