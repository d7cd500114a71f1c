"""Error against frame time of igi's ways past the paper's limits, one curve each, on the built-in
Cornell box, the built-in window room (sun and sky through one window), the same room with
venetian blinds in its window (--builtin blinds: the sun in stripes) and Sponza_lit:

  qmc + discontinuity       the paper's VPLs and filter (the default)
  importance                view-importance VPLs (--vpl-sampler importance)
  qmc + compensation        bias compensation, 4 gather rays (--compensate 4)
  qmc + atrous              the edge-avoiding a-trous filter (--filter atrous)
  qmc + roulette            shadow-ray Russian roulette at 0.2 (--roulette 0.2)
  temporal 8 / 32           temporal reuse of a still view: the 8th / 32nd frame of --temporal 8 / 32

each over VPLs per pixel 4 ... 64 at 3x3 interleaving, anti-aliasing 1. Every frame is compared
with a path-traced reference (rendered once and cached: --integrator path, jittered pixels) by
igi-compare --json; time is igi-render's median ms per frame over --frames frames (wall clock,
2 threads), so run it on a quiet machine.

usage: /usr/bin/python3 bench/accuracy/methods.py BUILD_DIR WORK_DIR OUT_DIR [SCENES_DIR]
writes OUT_DIR/methods.csv and OUT_DIR/methods.png.
"""

import csv
import json
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

SIZE = "320x240"  # a quarter of the showcase's pixels keeps references affordable
VPLS = [4, 8, 16, 32, 64]
FRAMES = 3  # timed frames per run; the median is reported
# Reference samples per pixel (in passes of 64): Sponza's paths are the costliest.
REFERENCE_SPP = {"cornell": 1024, "window": 1024, "blinds": 1024, "sponza_lit": 512}
# igi-render averages its --frames frames by default (temporal reuse); the methods but the temporal
# ones measure single frames, each independent of the frames before it, as the paper renders them.
INDEPENDENT_FRAMES = ["--temporal", "0"]
# (label, igi-render options, frames rendered: the last one is compared, their median timed)
METHODS = [
    ("qmc + discontinuity", INDEPENDENT_FRAMES, FRAMES),
    ("importance", [*INDEPENDENT_FRAMES, "--vpl-sampler", "importance"], FRAMES),
    ("qmc + compensation", [*INDEPENDENT_FRAMES, "--compensate", "4"], FRAMES),
    ("qmc + atrous", [*INDEPENDENT_FRAMES, "--filter", "atrous"], FRAMES),
    ("qmc + roulette", [*INDEPENDENT_FRAMES, "--roulette", "0.2"], FRAMES),
    ("temporal 8", ["--temporal", "8"], 8),
    ("temporal 32", ["--temporal", "32"], 32),
]


def scene_arguments(scene, scenes_dir):
    if scene == "sponza_lit":
        return [str(Path(scenes_dir) / "sponza" / "Sponza_lit.gltf")]
    return ["--builtin", scene]


def render(build, arguments, output):
    command = [str(Path(build) / "examples/render/igi-render"), *arguments, "--size", SIZE, "--threads", "2",
               "-o", str(output), "--stats", "json"]
    result = subprocess.run(command, check=True, capture_output=True, text=True)
    return json.loads(result.stdout.strip().splitlines()[-1])


def compare(build, reference, test):
    command = [str(Path(build) / "examples/compare/igi-compare"), "--json", str(reference), str(test)]
    return json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)


def write_csv(path, rows):
    """Writes `rows` (dicts with the same keys, the first one's order) to the CSV file `path`."""
    with open(path, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def arguments_and_references(tool):
    """BUILD_DIR, WORK_DIR, OUT_DIR and SCENES_DIR from the command line (the folders made), and the
    scenes to measure (Sponza_lit only where its file exists), each with its path-traced reference
    in WORK_DIR (rendered once, then reused), as [(scene, reference path)]."""
    build, work, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    scenes_dir = Path(sys.argv[4]) if len(sys.argv) > 4 else Path(__file__).resolve().parents[3] / "shared" / "scenes"
    work.mkdir(parents=True, exist_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    scenes = ["cornell", "window", "blinds"]
    if (scenes_dir / "sponza" / "Sponza_lit.gltf").exists():
        scenes.append("sponza_lit")
    else:
        print(f"{tool}: skipping sponza_lit: {scenes_dir}/sponza/Sponza_lit.gltf is missing")
    references = []
    for scene in scenes:
        reference = work / f"reference_{scene}.pfm"
        if not reference.exists():
            spp = REFERENCE_SPP[scene]
            print(f"{tool}: reference {scene}, {spp} spp", flush=True)
            render(build, scene_arguments(scene, scenes_dir) + ["--integrator", "path", "--spp", "64",
                                                                 "--frames", str(spp // 64)], reference)
        references.append((scene, reference))
    return build, work, out, scenes_dir, references


def main():
    build, work, out, scenes_dir, references = arguments_and_references("methods")
    scenes = [scene for scene, _ in references]
    rows = []
    for scene, reference in references:
        for label, options, frames in METHODS:
            for vpls in VPLS:
                test = work / f"{scene}_{label.replace(' ', '').replace('+', '_')}_{vpls}.pfm"
                stats = render(build, scene_arguments(scene, scenes_dir) + options +
                               ["--vpls", str(vpls), "--frames", str(frames)], test)
                error = compare(build, reference, test)
                rows.append({"scene": scene, "method": label, "vpls": vpls, "ms_per_frame": stats["ms_per_frame"],
                             "relmse": error["relmse"], "rmse": error["rmse"]})
                print(f"{scene:10} {label:22} M={vpls:3}: {stats['ms_per_frame']:8.1f} ms  relMSE {error['relmse']:.4f}",
                      flush=True)
    write_csv(out / "methods.csv", rows)
    figure, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4.2))
    for axis, scene in zip(axes, scenes):
        for label, _, _ in METHODS:
            points = sorted((r["ms_per_frame"], r["relmse"]) for r in rows if r["scene"] == scene and r["method"] == label)
            axis.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=label)
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_title(f"{scene}, {SIZE}, VPLs {VPLS[0]}-{VPLS[-1]}")
        axis.set_xlabel("ms per frame (2 threads)")
        axis.set_ylabel("relMSE against the path tracer")
        axis.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "methods.png", dpi=110)
    print(f"methods: wrote {out / 'methods.csv'} and {out / 'methods.png'}")


if __name__ == "__main__":
    main()
