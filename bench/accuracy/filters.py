"""The a-trous filter against the discontinuity buffer at equal frame time: on the built-in Cornell
box, the window room, the room with blinds (sun through slats) and Sponza_lit, each filter over
VPLs per pixel 4 ... 64 at 3x3 interleaving (with the sampler that scene's methods chart prefers:
QMC, and view importance for the two rooms lit through their window). relMSE against the
path-traced references of methods.py (rendered here if WORK_DIR lacks them) is the mean over
seeds 1-8, since one frame's error depends on its VPLs' luck, and that luck is heavy-tailed: on
the blinds at 16 VPLs seven seeds' errors lie within 0.016-0.023 and seed 6's is 0.129 (a few
strong VPLs light blotches), so three seeds (the first version) missed the frames a filter
changes most. Both filters shade the same VPLs with the same rays for a seed, so the ratio of
their errors per seed is a paired comparison at equal VPLs, reported as well. Time is measured
apart, the two filters' runs alternating (TIMING_ROUNDS pairs of TIMED_FRAMES frames, seed 1,
wall clock, 2 threads), and is each filter's median over its runs of their median ms per frame:
timed together, a drift of the machine's speed moves both filters alike, which the comparison at equal
time needs (the first version timed each filter in its own three 3-frame runs, and one slow run
moved a point by 15%). Run it on a quiet machine.

For each a-trous point the discontinuity buffer's relMSE at the same time is interpolated on its
curve (linearly in log time and log error between the two points around it); the ratio below 1
means a-trous wins at that budget. Points outside the other curve's time range are not compared.

usage: /usr/bin/python3 bench/accuracy/filters.py BUILD_DIR WORK_DIR OUT_DIR [SCENES_DIR]
writes OUT_DIR/filters.csv, OUT_DIR/filters.png and OUT_DIR/filters_findings.txt.
"""

import math
import statistics

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

from methods import (INDEPENDENT_FRAMES, SIZE, VPLS, arguments_and_references, compare, render, scene_arguments,
                     write_csv)

FILTERS = ["discontinuity", "atrous"]
SEEDS = list(range(1, 9))
FRAMES = 3  # frames per accuracy run; the last one is compared
TIMED_FRAMES = 8  # frames per timing run (their median is the run's time)
TIMING_ROUNDS = 5  # alternating pairs of timing runs per scene and M (3 left the 320 x 240 points +-2 ms apart)
# The VPL sampler each scene is measured with: importance wins the rooms lit through a window
# from 17 ms on (methods.png), QMC elsewhere.
SAMPLER = {"cornell": "qmc", "window": "importance", "blinds": "importance", "sponza_lit": "qmc"}


def interpolate(points, ms):
    """relMSE of the curve `points` [(ms, relmse)] at time `ms`, log-log linear; None outside it."""
    points = sorted(points)
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if t0 <= ms <= t1:
            if t1 == t0:
                return min(e0, e1)
            f = (math.log(ms) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return math.exp(math.log(e0) + f * (math.log(e1) - math.log(e0)))
    return None


def main():
    build, work, out, scenes_dir, references = arguments_and_references("filters")
    scenes = [scene for scene, _ in references]
    rows = []
    for scene, reference in references:
        sampler = SAMPLER[scene]
        for vpls in VPLS:
            def arguments(filter_name, frames, seed):
                return scene_arguments(scene, scenes_dir) + INDEPENDENT_FRAMES + [
                    "--filter", filter_name, "--vpl-sampler", sampler, "--vpls", str(vpls), "--frames", str(frames),
                    "--seed", str(seed)]
            times = {filter_name: [] for filter_name in FILTERS}
            for _ in range(TIMING_ROUNDS):
                for filter_name in FILTERS:
                    stats = render(build, arguments(filter_name, TIMED_FRAMES, SEEDS[0]),
                                   work / f"filters_{scene}_timing.pfm")
                    times[filter_name].append(stats["ms_per_frame"])
            for filter_name in FILTERS:
                errors = []
                for seed in SEEDS:
                    test = work / f"filters_{scene}_{filter_name}_{vpls}_{seed}.pfm"
                    render(build, arguments(filter_name, FRAMES, seed), test)
                    errors.append(compare(build, reference, test)["relmse"])
                rows.append({"scene": scene, "sampler": sampler, "filter": filter_name, "vpls": vpls,
                             "ms_per_frame": statistics.median(times[filter_name]),
                             "relmse": sum(errors) / len(errors), "relmse_median": statistics.median(errors),
                             "relmse_per_seed": " ".join(f"{e:.5f}" for e in errors)})
                print(f"{scene:10} {filter_name:13} M={vpls:3}: {rows[-1]['ms_per_frame']:7.1f} ms  "
                      f"relMSE {rows[-1]['relmse']:.5f}", flush=True)
    write_csv(out / "filters.csv", rows)

    findings = []
    for scene in scenes:
        def curve(filter_name):
            return [r for r in rows if r["scene"] == scene and r["filter"] == filter_name]
        discontinuity = [(r["ms_per_frame"], r["relmse"]) for r in curve("discontinuity")]
        compared = []  # (row of a-trous, its error over the discontinuity buffer's at that time)
        for row in curve("atrous"):
            other = interpolate(discontinuity, row["ms_per_frame"])
            if other is not None:
                compared.append((row, row["relmse"] / other))
        wins = sum(1 for _, ratio in compared if ratio < 1.0)
        findings.append(f"{scene} ({SAMPLER[scene]}): a-trous wins {wins} of {len(compared)} equal-time points; " +
                        "; ".join(f"M={row['vpls']} {row['ms_per_frame']:.1f} ms: {row['relmse']:.5f} against "
                                  f"{row['relmse'] / ratio:.5f} ({ratio:.2f})" for row, ratio in compared))
        paired = []
        for row in curve("atrous"):
            other = next(r for r in curve("discontinuity") if r["vpls"] == row["vpls"])
            ratios = [float(a) / float(d) for a, d in zip(row["relmse_per_seed"].split(), other["relmse_per_seed"].split())]
            paired.append(f"M={row['vpls']} less on {sum(1 for r in ratios if r < 1.0)} of {len(ratios)}, "
                          f"median {statistics.median(ratios):.2f}, range {min(ratios):.2f}-{max(ratios):.2f}")
        findings.append(f"{scene}: a-trous's error over the discontinuity buffer's per seed at equal VPLs: " +
                        "; ".join(paired))
    (out / "filters_findings.txt").write_text("\n".join(findings) + "\n")
    print("\n".join(findings))

    figure, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4.2))
    for axis, scene in zip(axes, scenes):
        for filter_name in FILTERS:
            points = sorted((r["ms_per_frame"], r["relmse"]) for r in rows
                            if r["scene"] == scene and r["filter"] == filter_name)
            axis.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=filter_name)
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_title(f"{scene} ({SAMPLER[scene]}), {SIZE}, seeds {SEEDS[0]}-{SEEDS[-1]}")
        axis.set_xlabel("ms per frame (2 threads)")
        axis.set_ylabel("mean relMSE against the path tracer")
        axis.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "filters.png", dpi=110)
    print(f"filters: wrote {out / 'filters.csv'}, {out / 'filters.png'} and {out / 'filters_findings.txt'}")


if __name__ == "__main__":
    main()
