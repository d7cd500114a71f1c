"""Error and frame time of igi's settings on an outdoor scene with foliage: the forest of
bench/scenes/forest.py (TREES trees of alpha-masked leaf cards on a 100 m ground, a low sun, no
sky), against igi's path tracer (REFERENCE_SPP jittered samples per pixel, rendered once and
cached in WORK_DIR) and against it sampling pixel centres as IGI does (igi-path-render
--pixel-centre: the error left without the leaves' sampling within each pixel; not a measure
for --aa, whose sub-samples spread over the pixel as the first reference's do). Each setting is rendered for seeds 1-3 (its errors are their mean, since
one frame's error depends on its VPLs' luck) and timed apart in TIMED_FRAMES frames (igi-render's
median, wall clock, 2 threads), so run it on a quiet machine.

What it shows (docs/accuracy.md, "Outdoors: foliage"): there the error is the camera rays' pixel-centre
sampling of the leaves, not the VPLs' noise, so anti-aliasing buys more than VPLs at equal time.

usage: /usr/bin/python3 bench/accuracy/outdoor.py BUILD_DIR WORK_DIR OUT_DIR [TREES]
writes OUT_DIR/outdoor.csv and OUT_DIR/outdoor_findings.txt.
"""

import statistics
import subprocess
import sys
from pathlib import Path

from methods import INDEPENDENT_FRAMES, SIZE, compare, render, write_csv

SEEDS = [1, 2, 3]  # three frames' VPLs: one frame's error depends on its VPLs' luck
TIMED_FRAMES = 5  # their median steadies a run on a shared machine
# In passes of 64. Two seeds of it differ by relMSE 0.0004, under 3% of the best setting's 0.017.
REFERENCE_SPP = 256
# (label, igi-render options)
SETTINGS = [
    ("16 VPLs", ["--vpls", "16"]),
    ("32 VPLs", ["--vpls", "32"]),
    ("64 VPLs", ["--vpls", "64"]),
    ("16 VPLs, aa 4", ["--vpls", "16", "--aa", "4"]),
    ("16 VPLs, compensate 4", ["--vpls", "16", "--compensate", "4"]),
    ("16 VPLs, importance", ["--vpls", "16", "--vpl-sampler", "importance"]),
]


def main():
    build, work, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    trees = int(sys.argv[4]) if len(sys.argv) > 4 else 300
    work.mkdir(parents=True, exist_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    generator = Path(__file__).resolve().parents[1] / "scenes" / "forest.py"
    scene = work / f"forest_{trees}.gltf"
    if not scene.exists():
        subprocess.run([sys.executable, str(generator), str(trees), str(work)], check=True)
    reference = work / f"reference_forest_{trees}.pfm"
    if not reference.exists():
        print(f"outdoor: reference, {REFERENCE_SPP} spp", flush=True)
        render(build, [str(scene), "--integrator", "path", "--spp", "64", "--frames", str(REFERENCE_SPP // 64)], reference)
    centre_reference = work / f"reference_forest_{trees}_centre.pfm"
    if not centre_reference.exists():
        print(f"outdoor: pixel-centre reference, {REFERENCE_SPP} spp", flush=True)
        subprocess.run([str(build / "bench/accuracy/igi-path-render"), str(scene), "--size", SIZE, "--spp",
                        str(REFERENCE_SPP), "--threads", "2", "--pixel-centre", "-o", str(centre_reference)],
                       check=True, capture_output=True)
    rows = []
    for label, options in SETTINGS:
        errors, centre_errors = [], []
        for seed in SEEDS:
            test = work / f"forest_{len(rows)}_{seed}.pfm"
            render(build, [str(scene), *INDEPENDENT_FRAMES, *options, "--seed", str(seed)], test)
            errors.append(compare(build, reference, test))
            centre_errors.append(compare(build, centre_reference, test))
        stats = render(build, [str(scene), *INDEPENDENT_FRAMES, *options, "--frames", str(TIMED_FRAMES)],
                       work / "forest_timing.pfm")
        rows.append({"setting": label, "ms_per_frame": stats["ms_per_frame"],
                     "relmse": statistics.mean(e["relmse"] for e in errors),
                     "rmse": statistics.mean(e["rmse"] for e in errors),
                     "ssim": statistics.mean(e["ssim"] for e in errors),
                     "relmse_pixel_centres": statistics.mean(e["relmse"] for e in centre_errors)})
        print(f"{label:24} {rows[-1]['ms_per_frame']:7.1f} ms  relMSE {rows[-1]['relmse']:.4f}  "
              f"RMSE {rows[-1]['rmse']:.4f}  SSIM {rows[-1]['ssim']:.3f}  "
              f"relMSE against pixel centres {rows[-1]['relmse_pixel_centres']:.4f}", flush=True)
    write_csv(out / "outdoor.csv", rows)
    with open(out / "outdoor_findings.txt", "w") as findings:
        findings.write(f"forest of {trees} trees, {SIZE}, against the path tracer at {REFERENCE_SPP} spp, seeds 1-3:\n")
        for row in rows:
            findings.write(f"  {row['setting']:24} {row['ms_per_frame']:7.1f} ms  relMSE {row['relmse']:.4f}  "
                           f"RMSE {row['rmse']:.4f}  SSIM {row['ssim']:.3f}  "
                           f"relMSE against pixel centres {row['relmse_pixel_centres']:.4f}\n")
    print(f"outdoor: wrote {out / 'outdoor.csv'} and {out / 'outdoor_findings.txt'}")


if __name__ == "__main__":
    main()
