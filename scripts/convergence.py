#!/usr/bin/python3
"""Error against time for every algorithm on one scene.

Renders a reference (vcm, the one estimator that samples every kind of path
in the bundled scenes, including caustics seen through glass, with a merge
radius that shrinks so its bias vanishes), then runs each algorithm for the
same wall-clock time with `wavevcm render --error-log`, and plots RMSE
against render time on log-log axes with the fitted convergence slope of
each in the legend (PNG and SVG). The CSV logs stay in the output directory;
scripts/convergence_table.py turns them into a Markdown table.

    /usr/bin/python3 scripts/convergence.py scenes/cornell-box.gltf \\
        --seconds 20 --reference-seconds 120 --out results/cornell-box

Needs Debian's python3-matplotlib and python3-numpy (run with /usr/bin/python3).
"""

import argparse
import csv
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALGORITHMS = ["pt", "lt", "bpt", "ppm", "bpm", "vcm"]


def read_log(path):
    """(seconds, iterations, rmse, relmse) rows of an --error-log CSV."""
    with open(path) as f:
        rows = [line for line in f if not line.startswith("#")]
    return [(float(r["seconds"]), int(r["iterations"]), float(r["rmse"]), float(r["relmse"]))
            for r in csv.DictReader(rows)]


def fitted_slope(rows):
    """Least-squares slope of log RMSE against log time over the last 90 % of
    the run (the first iterations carry start-up effects)."""
    import numpy as np
    if len(rows) < 3:
        return float("nan")
    end = rows[-1][0]
    kept = [r for r in rows if r[0] >= 0.1 * end and r[2] > 0] or rows
    if len(kept) < 2:
        return float("nan")
    x = np.log([r[0] for r in kept])
    y = np.log([r[2] for r in kept])
    return float(np.polyfit(x, y, 1)[0])


def run(args, extra):
    command = [args.wavevcm, "render", args.scene, "-q", "--height", str(args.height),
               "-d", args.device] + extra
    print("+", " ".join(command), file=sys.stderr)
    subprocess.run(command, check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--seconds", type=float, default=20, help="render time per algorithm")
    parser.add_argument("--reference-seconds", type=float, default=120)
    parser.add_argument("--height", type=int, default=128, help="image height in pixels")
    parser.add_argument("--device", default="0", help="as `wavevcm render --device`")
    parser.add_argument("--algorithms", default=",".join(ALGORITHMS))
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--wavevcm", default=os.path.join(REPO, "build", "wavevcm"))
    args = parser.parse_args()

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.out, exist_ok=True)
    reference = os.path.join(args.out, "reference.exr")
    if not os.path.exists(reference):
        run(args, ["-a", "vcm", "-t", str(args.reference_seconds), "--seed", "1000", "-o", reference])

    name = os.path.splitext(os.path.basename(args.scene))[0]
    figure, axes = plt.subplots(figsize=(7, 5))
    for algorithm in args.algorithms.split(","):
        log = os.path.join(args.out, algorithm + ".csv")
        run(args, ["-a", algorithm, "-t", str(args.seconds), "--reference", reference,
                   "--error-log", log, "-o", os.path.join(args.out, algorithm + ".exr")])
        rows = read_log(log)
        axes.loglog([r[0] for r in rows], [r[2] for r in rows],
                    label="%s (slope %.2f)" % (algorithm, fitted_slope(rows)))
    axes.set_xlabel("render time [s]")
    axes.set_ylabel("RMSE against the reference")
    axes.set_title("%s, %d px high" % (name, args.height))
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    for extension in ("png", "svg"):
        figure.savefig(os.path.join(args.out, "error-vs-time." + extension))


if __name__ == "__main__":
    main()
