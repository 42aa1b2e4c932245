#!/usr/bin/env bash
# The ray-casting tables of docs/performance.md in one command: writes the benchmark scenes
# (scripts/make_scenes.py: the 130K-triangle Cornell box and the 1M-triangle
# displaced sphere) into build/bench-scenes if missing, runs wavevcm_bench's
# ray benchmarks on each scene and the BVH build benchmark, and prints
# Markdown tables with Embree's rate and the ratio beside every figure.
# Usage: scripts/bench_tables.sh  (settings from the environment:
#   DEVICE=pthread RAYS=262144 MIN_TIME=1 BUILD=build; MIN_TIME is seconds of
#   wavevcm launches per benchmark, each paired with an Embree run: the ratio
#   is their median, and 1 s gives 5-30 pairs where 0.3 s gave 2-10)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build}
device=${DEVICE:-pthread}
rays=${RAYS:-262144}
min_time=${MIN_TIME:-1}
bench="$build/wavevcm_bench"
[ -x "$bench" ] || { echo "bench_tables: build $bench first (cmake --build $build)" >&2; exit 1; }
scenes_dir="${SCENES_DIR:-$build/bench-scenes}"
for name in cornell-box-130k displaced-1m; do
  [ -f "$scenes_dir/$name.gltf" ] || python3 scripts/make_scenes.py "$name" -d "$scenes_dir" >&2
done
scenes="scenes/cornell-box.gltf scenes/caustics.gltf $scenes_dir/cornell-box-130k.gltf $scenes_dir/displaced-1m.gltf"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
i=0
for scene in $scenes; do
  echo "bench_tables: $scene" >&2
  WAVEVCM_BENCH_SCENE="$scene" WAVEVCM_BENCH_DEVICE="$device" "$bench" \
    --benchmark_filter="BM_(Extend|Connect)(Coherent|Incoherent)/$rays/" \
    --benchmark_min_time="$min_time" --benchmark_format=json > "$work/rays$i.json" 2>"$work/rays$i.err" ||
    { cat "$work/rays$i.err" >&2; exit 1; }
  i=$((i + 1))
done
"$bench" --benchmark_filter='BM_BvhBuild/(1048576|4194304)$' --benchmark_format=json > "$work/build.json" 2>/dev/null
python3 - "$work" $scenes <<'PY'
import json, os, re, sys
work, scenes = sys.argv[1], sys.argv[2:]
def load(path):
    with open(path) as f:
        return json.load(f)["benchmarks"]
def triangles(path):
    """Triangles as rendered: a mesh counts once per node that uses it."""
    with open(path) as f:
        doc = json.load(f)
    uses = {}
    for node in doc.get("nodes", []):
        if "mesh" in node:
            uses[node["mesh"]] = uses.get(node["mesh"], 0) + 1
    return sum(sum(doc["accessors"][p["indices"]]["count"] // 3 for p in doc["meshes"][m]["primitives"]) * n
               for m, n in uses.items())
rows = [("ExtendCoherent", "extend, coherent"), ("ExtendIncoherent", "extend, incoherent"),
        ("ConnectCoherent", "connect (any hit), coherent"), ("ConnectIncoherent", "connect (any hit), incoherent")]
results = [{re.sub(r"/.*", "", b["name"]).replace("BM_", ""): b for b in load(os.path.join(work, "rays%d.json" % i))}
           for i in range(len(scenes))]
names = ["%s (%s triangles)" % (os.path.basename(s).replace(".gltf", ""), format(triangles(s), ",")) for s in scenes]
print("| benchmark | " + " | ".join(names) + " |")
print("| --- |" + " --- |" * len(scenes))
for key, label in rows:
    cells = []
    for r in results:
        b = r.get(key)
        if b is None:
            cells.append("-")
        elif "embree_rays_per_s" in b:
            cells.append("%.1f M (Embree %.1f M: %.2f×)" % (b["items_per_second"] / 1e6, b["embree_rays_per_s"] / 1e6, b["vs_embree"]))
        else:
            cells.append("%.1f M" % (b["items_per_second"] / 1e6))
    print("| %s | %s |" % (label, " | ".join(cells)))
print()
print("| BVH build | time | triangles/s | SAH cost |")
print("| --- | --- | --- | --- |")
for b in load(os.path.join(work, "build.json")):
    n = int(b["name"].split("/")[1])
    sah = "%.2f" % b["sah_cost"] if "sah_cost" in b else "-"  # older builds do not report it
    print("| %s triangles | %.2f s | %.2f M | %s |" % (format(n, ","), b["real_time"] / 1e3, b["items_per_second"] / 1e6, sah))
PY
