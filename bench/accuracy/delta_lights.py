"""The delta lights' direct light composed per pixel (igi's default) against the paper's way,
filtered with the VPLs' light (--filter-delta-lights), on the scenes of methods.py that have a
delta light (the sun of the window room, the blinds and Sponza_lit; the Cornell box has only its
area light, where both ways are the same image): 320x240, 16 VPLs per pixel, 3x3, the
discontinuity and the a-trous filter, aa 1 and 4, with the sampler filters.py uses per scene;
relMSE and RMSE against the path-traced references of methods.py (rendered here if WORK_DIR
lacks them), each the mean over the seeds filters.py averages (1-8), and the median ms per frame
(2 threads).

usage: /usr/bin/python3 bench/accuracy/delta_lights.py BUILD_DIR WORK_DIR OUT_DIR [SCENES_DIR]
writes OUT_DIR/delta_lights.csv and OUT_DIR/delta_lights_findings.txt.
"""

import statistics

from filters import SAMPLER, SEEDS
from methods import INDEPENDENT_FRAMES, arguments_and_references, compare, render, scene_arguments, write_csv

VPLS = 16
FRAMES = 3  # timed frames per run; the last one is compared
WAYS = [("composed", []), ("filtered", ["--filter-delta-lights"])]


def main():
    build, work, out, scenes_dir, references = arguments_and_references("delta_lights")
    rows = []
    for scene, reference in references:
        if scene == "cornell":
            continue  # no delta light: both ways are the same frame
        for filter_name in ["discontinuity", "atrous"]:
            for antialiasing in [1, 4]:
                for way, options in WAYS:
                    times, relmse, rmse = [], [], []
                    for seed in SEEDS:
                        test = work / f"delta_{scene}_{filter_name}_{antialiasing}_{way}_{seed}.pfm"
                        stats = render(build, scene_arguments(scene, scenes_dir) + INDEPENDENT_FRAMES + options +
                                       ["--filter", filter_name, "--vpl-sampler", SAMPLER[scene], "--vpls", str(VPLS),
                                        "--aa", str(antialiasing), "--frames", str(FRAMES), "--seed", str(seed)], test)
                        error = compare(build, reference, test)
                        times.append(stats["ms_per_frame"])
                        relmse.append(error["relmse"])
                        rmse.append(error["rmse"])
                    rows.append({"scene": scene, "sampler": SAMPLER[scene], "filter": filter_name, "aa": antialiasing,
                                 "delta_lights": way, "ms_per_frame": statistics.median(times),
                                 "relmse": sum(relmse) / len(relmse), "rmse": sum(rmse) / len(rmse)})
                    print(f"{scene:10} {filter_name:13} aa {antialiasing} {way:9}: {rows[-1]['ms_per_frame']:7.1f} ms  "
                          f"relMSE {rows[-1]['relmse']:.5f}  RMSE {rows[-1]['rmse']:.5f}", flush=True)
    write_csv(out / "delta_lights.csv", rows)

    findings = []
    for row in rows:
        if row["delta_lights"] != "composed":
            continue
        filtered = next(r for r in rows if r["delta_lights"] == "filtered" and
                        all(r[key] == row[key] for key in ["scene", "filter", "aa"]))
        findings.append(f"{row['scene']} ({row['sampler']}), {row['filter']}, aa {row['aa']}: composed/filtered "
                        f"relMSE {row['relmse']:.5f}/{filtered['relmse']:.5f} ({row['relmse'] / filtered['relmse']:.2f}), "
                        f"RMSE {row['rmse']:.5f}/{filtered['rmse']:.5f} ({row['rmse'] / filtered['rmse']:.2f}), "
                        f"{row['ms_per_frame']:.1f}/{filtered['ms_per_frame']:.1f} ms")
    (out / "delta_lights_findings.txt").write_text("\n".join(findings) + "\n")
    print("\n".join(findings))
    print(f"delta_lights: wrote {out / 'delta_lights.csv'} and {out / 'delta_lights_findings.txt'}")


if __name__ == "__main__":
    main()
