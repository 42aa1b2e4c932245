"""wavevcm against SmallVCM, the VCM paper's scalar CPU reference renderer
(Davidovic and Georgiev), on the same Cornell boxes for the same wall time,
on the same machine: iterations per second and error at equal time for each
algorithm both implement (pt, lt, bpt, ppm, bpm, vcm).

Run through scripts/compare_smallvcm.sh, which builds SmallVCM (two binaries
that differ only in their base seed) and passes its options on.

SmallVCM's scenes are built into its code; scripts/make_scenes.py writes
glTF versions of two of them (smallvcm-area: its scene 1, a large mirror
sphere under the ceiling's light box; smallvcm-point: its scene 2, a mirror
and a glass sphere under a point light). Its analytic spheres become
triangles and its Phong floor a GGX one, so the images differ a little, and
each renderer is measured against references of its own.

References: a long bpt and a long vcm render of each renderer, with seeds
other than the equal-time runs'. bpt is measured against the vcm reference,
every other algorithm against the bpt one: SmallVCM's threads start from the
same seeds in every run, so a reference of the same algorithm would share its
first iterations with the run it measures, and pt's or lt's camera samples
with bpt's. The merging algorithms' error then includes their bias (their
radius shrinks over iterations), as it does for a user.

SmallVCM's -t counts CPU time summed over its threads, so it runs a fixed
number of iterations instead, chosen from a first short run to take about
the wall time asked for (redone once if more than 10 % off it); each run's
relMSE is then scaled to the asked-for time (relMSE x wall / seconds: the
error of an estimator that converges as 1/time).
"""

import argparse
import json
import os
import subprocess
import sys
import time

from comparelib import machine, relmse

SCENES = {"area": ("smallvcm-area", 1), "point": ("smallvcm-point", 2)}
ALGORITHMS = ["pt", "lt", "bpt", "ppm", "bpm", "vcm"]


def run_smallvcm(binary, scene_id, algorithm, iterations, out):
    start = time.perf_counter()
    subprocess.run([binary, "-s", str(scene_id), "-a", algorithm, "-i", str(iterations), "-o", out],
                   check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def smallvcm_iterations(binary, scene_id, algorithm, seconds, threads, out):
    """Iterations that take about `seconds` of wall time: a multiple of the
    thread count (its OpenMP loop gives each thread an equal share)."""
    one_round = run_smallvcm(binary, scene_id, algorithm, threads, out)
    return threads * max(1, int(round(seconds / one_round)))


def run_smallvcm_for(binary, scene_id, algorithm, seconds, threads, out):
    """Renders for about `seconds` of wall time; returns the iterations and
    the wall time. A run more than 10 % off the time (the first round's
    estimate includes the start) is redone with the iterations scaled: an
    error with a bias in it (merging's, or what an algorithm cannot render)
    does not scale with time."""
    n = smallvcm_iterations(binary, scene_id, algorithm, seconds, threads, out)
    wall = run_smallvcm(binary, scene_id, algorithm, n, out)
    if abs(wall - seconds) > 0.1 * seconds:
        n = threads * max(1, int(round(n * seconds / wall / threads)))
        wall = run_smallvcm(binary, scene_id, algorithm, n, out)
    return n, wall


def run_wavevcm(binary, scene, algorithm, seconds, seed, out):
    stats = out + ".json"
    subprocess.run([binary, "render", scene, "-a", algorithm, "-t", str(seconds), "--width", "512", "--height", "512",
                    "--max-path-length", "10", "--seed", str(seed), "-q", "-o", out, "--stats", stats], check=True)
    with open(stats) as f:
        s = json.load(f)
    return s["iterations"], s["render_seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smallvcm", required=True, help="SmallVCM binary (seed 1234, as released)")
    ap.add_argument("--smallvcm-reseeded", required=True, help="the same with another base seed, for references")
    ap.add_argument("--scenes", default="area,point", help="comma-separated: " + ", ".join(SCENES))
    ap.add_argument("--algorithms", default=",".join(ALGORITHMS))
    ap.add_argument("--seconds", type=float, default=30.0, help="wall time of each equal-time render")
    ap.add_argument("--reference-seconds", type=float, default=120.0, help="wall time of each reference")
    ap.add_argument("--keep-references", action="store_true",
                    help="reuse the references an earlier run left in --out (same scenes and renderers only)")
    ap.add_argument("--wavevcm", default="build/wavevcm")
    ap.add_argument("--out", default="build/smallvcm-compare")
    args = ap.parse_args()

    threads = os.cpu_count()
    os.makedirs(args.out, exist_ok=True)
    o = lambda name: os.path.join(args.out, name)
    scene_names = args.scenes.split(",")
    algorithms = args.algorithms.split(",")
    for name in scene_names + algorithms:
        if name not in SCENES and name not in ALGORITHMS:
            sys.exit("compare_smallvcm: unknown scene or algorithm '%s'" % name)
    subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "make_scenes.py"), "-d", args.out] +
                   [SCENES[s][0] for s in scene_names], check=True, stdout=subprocess.DEVNULL)

    print("machine: %s; SmallVCM with %d OpenMP threads, wavevcm on its default device" % (machine(), threads))
    for scene_name in scene_names:
        gltf, scene_id = o(SCENES[scene_name][0] + ".gltf"), SCENES[scene_name][1]
        log = lambda what: print("compare_smallvcm: %s: %s" % (scene_name, what), file=sys.stderr, flush=True)
        for reference in ("bpt", "vcm"):
            images = (o("%s-smallvcm-ref-%s.hdr" % (scene_name, reference)),
                      o("%s-wavevcm-ref-%s.exr" % (scene_name, reference)))
            if args.keep_references and all(os.path.exists(image) for image in images):
                log("%s references kept from an earlier run" % reference)
                continue
            log("%s references (%g s each)" % (reference, args.reference_seconds))
            run_smallvcm_for(args.smallvcm_reseeded, scene_id, reference, args.reference_seconds, threads, images[0])
            run_wavevcm(args.wavevcm, gltf, reference, args.reference_seconds, 1 << 20, images[1])
        rows = []
        for algorithm in algorithms:
            log("%s (%g s each)" % (algorithm, args.seconds))
            reference = "vcm" if algorithm == "bpt" else "bpt"
            image = o("%s-smallvcm-%s.hdr" % (scene_name, algorithm))
            n, wall = run_smallvcm_for(args.smallvcm, scene_id, algorithm, args.seconds, threads, image)
            s_err = relmse(args.wavevcm, image, o("%s-smallvcm-ref-%s.hdr" % (scene_name, reference))) * wall / args.seconds
            image = o("%s-wavevcm-%s.exr" % (scene_name, algorithm))
            w_its, w_wall = run_wavevcm(args.wavevcm, gltf, algorithm, args.seconds, 1, image)
            w_err = relmse(args.wavevcm, image, o("%s-wavevcm-ref-%s.exr" % (scene_name, reference))) * w_wall / args.seconds
            rows.append((algorithm, n, wall, s_err, w_its, w_wall, w_err))

        print("\n%s (SmallVCM scene %d, %s), 512x512, max path length 10, %g s each:\n" %
              (scene_name, scene_id, os.path.basename(gltf), args.seconds))
        print("| algorithm | SmallVCM: iterations, s, it/s, relMSE | wavevcm: iterations, s, it/s, relMSE "
              "| wavevcm / SmallVCM: it/s | relMSE at equal time |")
        print("| --- | --- | --- | --- | --- |")
        for algorithm, n, wall, s_err, w_its, w_wall, w_err in rows:
            print("| %s | %d, %.1f, %.2f, %.4g | %d, %.1f, %.2f, %.4g | %.2fx | %.2fx |" %
                  (algorithm, n, wall, n / wall, s_err, w_its, w_wall, w_its / w_wall, w_err,
                   (w_its / w_wall) / (n / wall), w_err / s_err))
        print("\nrelMSE between the two renderers' vcm references (same-scene check): %.4g" %
              relmse(args.wavevcm, o("%s-wavevcm-ref-vcm.exr" % scene_name),
                     o("%s-smallvcm-ref-vcm.hdr" % scene_name)))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
