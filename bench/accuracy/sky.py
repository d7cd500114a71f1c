"""The environment light (--environment) and portals (--portal-share) measured against igi's path
tracer, in parts:

  directions  outdoors: the forest of bench/scenes/forest.py (TREES trees, its sun plus
              --environment neutral) and Sponza.gltf (no lights, so the neutral sky by default:
              the atrium lit from its open roof), over --environment-directions K in DIRECTIONS,
              VPLS VPLs, seeds 1-3; plus the path tracer at 1 and 4 spp (equal-time check).
  portals     window-lit rooms: window-sky, blinds-sky, two-windows and Sponza.gltf under the
              default sky, over --portal-share in SHARES, seeds 1-8: relMSE mean and median, each
              seed's image mean over the reference's (min, max, coefficient of variation).
  sun         the same for window-sky with --environment none (the sun alone).
  clamp       the rooms again without the clamp (--clamp 0), shares 0 and 0.7: how much of their
              darkness the clamp makes.
  converge    the rooms at 256 VPLs, shares 0 and 0.7, seeds 1-3: whether it goes with more VPLs.
  samplers    the window-lit rooms (the sky rooms, the sun alone, and the built-in window and
              blinds rooms lit by their sky panel) at the default share, seeds 1-16, with
              --vpl-sampler qmc and importance; the coefficient of variation also over seeds 1-8.

References: igi-path-render --pixel-centre (IGI samples pixel centres), REFERENCE_SPP per seed,
seeds 1 and 2, cached in WORK_DIR; the reference is their average (2 x REFERENCE_SPP), and the
relMSE between the two seeds is reported as the reference's own noise (the average's noise is
about a quarter of it). Error: igi-compare --json (relMSE with its epsilon 0.01). Time: igi-render's
ms_per_frame (the median of --frames 3; wall clock, 2 threads; the machine is shared, so timings
are noisy). Every run has a timeout.

usage: python3 bench/accuracy/sky.py BUILD_DIR WORK_DIR OUT_DIR [PARTS] [SCENES_DIR] [TREES]
  PARTS: a comma-separated subset of portals,sun,clamp,converge,directions,samplers (default: all
  but samplers, about 25 minutes on 2 busy cores; a subset writes sky_PARTS.csv and
  sky_PARTS_findings.txt instead; samplers takes about 4 minutes with the references cached)
writes OUT_DIR/sky.csv and OUT_DIR/sky_findings.txt (and OUT_DIR/sky.png if matplotlib imports).
"""

import array
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

SIZE = "320x240"
VPLS = 16
DIRECTIONS = [4, 8, 16, 32, 64, 128]
DIRECTION_SEEDS = [1, 2, 3]
SHARES = [0.0, 0.5, 0.7, 0.9]
PORTAL_SEEDS = list(range(1, 9))
REFERENCE_SPP = 256  # per seed; two seeds averaged
TIMED_FRAMES = 3
ALL_PARTS = "portals,sun,clamp,converge,directions"
TIMEOUT = 600  # seconds per igi run
REFERENCE_TIMEOUT = 900


def scene_arguments(scene, scenes_dir, work, trees):
    sponza = [str(Path(scenes_dir) / "sponza" / "Sponza.gltf")]
    return {
        "forest": [str(Path(work) / f"forest_{trees}.gltf"), "--environment", "neutral"],
        "sponza": sponza,
        "window-sky": ["--builtin", "window-sky"],
        "blinds-sky": ["--builtin", "blinds-sky"],
        "two-windows": ["--builtin", "two-windows"],
        "window-sun": ["--builtin", "window-sky", "--environment", "none"],
        "window": ["--builtin", "window"],
        "blinds": ["--builtin", "blinds"],
    }[scene]


def read_pfm(path):
    """(width, height, floats) of an RGB PFM (rows bottom-up, as written; the order is kept)."""
    data = Path(path).read_bytes()
    fields, position = [], 0
    while len(fields) < 4:  # magic, width, height, scale
        while data[position:position + 1].isspace():
            position += 1
        start = position
        while not data[position:position + 1].isspace():
            position += 1
        fields.append(data[start:position].decode())
    position += 1
    assert fields[0] == "PF", f"{path}: not an RGB PFM"
    width, height, scale = int(fields[1]), int(fields[2]), float(fields[3])
    values = array.array("f")
    values.frombytes(data[position:position + width * height * 12])
    if scale > 0:
        values.byteswap()  # big-endian
    return width, height, values


def write_pfm(path, width, height, values):
    with open(path, "wb") as file:
        file.write(f"PF\n{width} {height}\n-1\n".encode())
        file.write(values.tobytes())


def image_mean(path):
    _, _, values = read_pfm(path)
    return sum(values) / len(values)


def render(build, arguments, output, timeout=TIMEOUT):
    # --temporal 0: every run measures single frames (igi-render averages its --frames by default).
    command = [str(Path(build) / "examples/render/igi-render"), *arguments, "--size", SIZE, "--threads", "2",
               "--temporal", "0", "-o", str(output), "--stats", "json"]
    result = subprocess.run(command, check=True, capture_output=True, text=True, timeout=timeout)
    return json.loads(result.stdout.strip().splitlines()[-1])


def path_render(build, arguments, output, spp, seed, timeout=REFERENCE_TIMEOUT):
    """igi-path-render at pixel centres; returns its seconds (from its report line)."""
    command = [str(Path(build) / "bench/accuracy/igi-path-render"), *arguments, "--size", SIZE, "--spp", str(spp),
               "--seed", str(seed), "--pixel-centre", "--threads", "2", "-o", str(output)]
    result = subprocess.run(command, check=True, capture_output=True, text=True, timeout=timeout)
    line = (result.stdout + result.stderr).strip().splitlines()[-1]  # "...: WxH, N spp in S s; ..."
    return float(line.split(" spp in ")[1].split(" s")[0])


def compare(build, reference, test):
    command = [str(Path(build) / "examples/compare/igi-compare"), "--json", str(reference), str(test)]
    return json.loads(subprocess.run(command, check=True, capture_output=True, text=True, timeout=120).stdout)


def reference(build, work, scene, arguments):
    """The averaged two-seed reference of `scene` (rendered once) and the relMSE between its seeds."""
    seeds = []
    for seed in (1, 2):
        path = work / f"ref_{scene}_s{seed}.pfm"
        pending = Path(f"{path}.tmp.pfm")
        while not path.exists() and (work / "refs.running").exists():  # another process renders the references
            time.sleep(5)
        if not path.exists():
            print(f"sky: reference {scene} seed {seed}, {REFERENCE_SPP} spp", flush=True)
            path_render(build, arguments, pending, REFERENCE_SPP, seed)
            pending.rename(path)
        seeds.append(path)
    average = work / f"ref_{scene}.pfm"
    if not average.exists():
        (w, h, a), (_, _, b) = read_pfm(seeds[0]), read_pfm(seeds[1])
        write_pfm(average, w, h, array.array("f", ((x + y) * 0.5 for x, y in zip(a, b))))
    noise = compare(build, seeds[0], seeds[1])["relmse"]
    return average, noise, image_mean(average)


def write_csv(path, rows):
    import csv
    keys = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    with open(path, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)


def cv(values):
    return statistics.pstdev(values) / statistics.mean(values)


def directions_part(build, work, scenes_dir, trees, log):
    rows = []
    for scene in ["forest", "sponza"]:
        arguments = scene_arguments(scene, scenes_dir, work, trees)
        ref, noise, ref_mean = reference(build, work, scene, arguments)
        log(f"\n[directions] {scene}: {SIZE}, {VPLS} VPLs, seeds {DIRECTION_SEEDS[0]}-{DIRECTION_SEEDS[-1]}; reference "
            f"{2 * REFERENCE_SPP} spp pixel-centre path tracer (seed 1 vs 2 relMSE {noise:.4f}), mean {ref_mean:.4f}")
        log(f"  {'K':>4} {'relMSE':>8} {'(min-max)':>17} {'mean/ref':>9} {'ms/frame':>9} {'VPLs/frame':>10}")
        for k in DIRECTIONS:
            errors, ratios = [], []
            for seed in DIRECTION_SEEDS:
                test = work / f"dir_{scene}_k{k}_s{seed}.pfm"
                stats = render(build, arguments + ["--vpls", str(VPLS), "--environment-directions", str(k),
                                                   "--seed", str(seed)], test)
                errors.append(compare(build, ref, test)["relmse"])
                ratios.append(image_mean(test) / ref_mean)
            timing = render(build, arguments + ["--vpls", str(VPLS), "--environment-directions", str(k),
                                                "--frames", str(TIMED_FRAMES)], work / "timing.pfm")
            row = {"part": "directions", "scene": scene, "setting": f"K={k}", "directions": k, "portal_share": 0.5,
                   "vpls": VPLS, "seeds": len(DIRECTION_SEEDS), "relmse_mean": statistics.mean(errors),
                   "relmse_median": statistics.median(errors), "relmse_min": min(errors), "relmse_max": max(errors),
                   "mean_ratio_mean": statistics.mean(ratios), "mean_ratio_min": min(ratios),
                   "mean_ratio_max": max(ratios), "mean_ratio_cv": cv(ratios), "ms_per_frame": timing["ms_per_frame"],
                   "vpls_per_frame": timing["vpls_per_frame"], "reference_noise_relmse": noise}
            rows.append(row)
            log(f"  {k:4} {row['relmse_mean']:8.4f} ({min(errors):.4f}-{max(errors):.4f}) {row['mean_ratio_mean']:9.3f} "
                f"{row['ms_per_frame']:9.1f} {row['vpls_per_frame']:10}")
        # The path tracer near equal time (pixel centres, as the reference).
        for spp in (1, 4):
            errors, seconds = [], []
            for seed in DIRECTION_SEEDS:
                test = work / f"dir_{scene}_pt{spp}_s{seed}.pfm"
                seconds.append(path_render(build, arguments, test, spp, 100 + seed))
                errors.append(compare(build, ref, test)["relmse"])
            row = {"part": "directions", "scene": scene, "setting": f"path tracer {spp} spp", "directions": "",
                   "vpls": "", "seeds": len(DIRECTION_SEEDS), "relmse_mean": statistics.mean(errors),
                   "relmse_median": statistics.median(errors), "relmse_min": min(errors), "relmse_max": max(errors),
                   "ms_per_frame": 1000 * statistics.median(seconds), "reference_noise_relmse": noise}
            rows.append(row)
            log(f"  path tracer {spp} spp: relMSE {row['relmse_mean']:.4f} ({min(errors):.4f}-{max(errors):.4f}), "
                f"{row['ms_per_frame']:.0f} ms (median of {len(seconds)})")
    return rows


def portals_part(build, work, scenes_dir, trees, scenes, log, shares=SHARES, extra=(), tag="portals", vpls=VPLS,
                 seeds=PORTAL_SEEDS):
    rows = []
    for scene in scenes:
        arguments = scene_arguments(scene, scenes_dir, work, trees)
        ref, noise, ref_mean = reference(build, work, scene, arguments)
        log(f"\n[{tag}] {scene}: {SIZE}, {vpls} VPLs, default K{' '.join([''] + list(extra))}, seeds {seeds[0]}-{seeds[-1]}; reference "
            f"{2 * REFERENCE_SPP} spp pixel-centre path tracer (seed 1 vs 2 relMSE {noise:.4f}), mean {ref_mean:.4f}")
        log(f"  {'share':>5} {'relMSE mean':>11} {'median':>7} {'max':>7} {'mean/ref min':>12} {'max':>6} {'CV':>6} "
            f"{'ms/frame':>9} {'VPLs/frame':>10}")
        base = None
        for share in shares:
            errors, ratios = [], []
            for seed in seeds:
                test = work / f"{tag}_{scene}_a{share}_s{seed}.pfm"
                render(build, arguments + [*extra, "--vpls", str(vpls), "--portal-share", str(share), "--seed", str(seed)],
                       test)
                errors.append(compare(build, ref, test)["relmse"])
                ratios.append(image_mean(test) / ref_mean)
            timing = render(build, arguments + [*extra, "--vpls", str(vpls), "--portal-share", str(share),
                                                "--frames", str(TIMED_FRAMES)], work / "timing.pfm")
            row = {"part": tag, "scene": scene, "setting": " ".join([f"share {share}", *extra]), "directions": 32,
                   "portal_share": share, "vpls": vpls, "seeds": len(seeds),
                   "relmse_mean": statistics.mean(errors), "relmse_median": statistics.median(errors),
                   "relmse_min": min(errors), "relmse_max": max(errors), "mean_ratio_mean": statistics.mean(ratios),
                   "mean_ratio_min": min(ratios), "mean_ratio_max": max(ratios), "mean_ratio_cv": cv(ratios),
                   "ms_per_frame": timing["ms_per_frame"], "vpls_per_frame": timing["vpls_per_frame"],
                   "reference_noise_relmse": noise, "relmse_per_seed": " ".join(f"{e:.4f}" for e in errors),
                   "mean_ratio_per_seed": " ".join(f"{r:.3f}" for r in ratios)}
            if base is None:
                base = row
            row["relmse_mean_over_share0"] = row["relmse_mean"] / base["relmse_mean"]
            row["relmse_median_over_share0"] = row["relmse_median"] / base["relmse_median"]
            row["target_half_error_met"] = row["relmse_mean_over_share0"] <= 0.5 if share > 0 else ""
            row["target_cv_met"] = row["mean_ratio_cv"] <= 0.05
            if len(ratios) > 8:  # the target's own seeds, 1-8
                row["mean_ratio_cv_seeds_1_8"] = cv(ratios[:8])
            rows.append(row)
            log(f"  {share:5} {row['relmse_mean']:11.4f} {row['relmse_median']:7.4f} {max(errors):7.4f} "
                f"{min(ratios):12.3f} {max(ratios):6.3f} {100 * row['mean_ratio_cv']:5.1f}% {row['ms_per_frame']:9.1f} "
                f"{row['vpls_per_frame']:10}   mean/share0 {row['relmse_mean_over_share0']:.2f}, "
                f"median/share0 {row['relmse_median_over_share0']:.2f}")
            if "mean_ratio_cv_seeds_1_8" in row:
                log(f"        CV over seeds 1-8 {100 * row['mean_ratio_cv_seeds_1_8']:.1f}%")
            log(f"        relMSE per seed {row['relmse_per_seed']}; mean/ref per seed {row['mean_ratio_per_seed']}")
    return rows


def chart(out, rows):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    figure, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for scene in sorted({r["scene"] for r in rows if r["part"] == "directions"}):
        points = [r for r in rows if r["part"] == "directions" and r["scene"] == scene and r["directions"] != ""]
        axes[0].plot([r["directions"] for r in points], [r["relmse_mean"] for r in points], marker="o", label=scene)
    axes[0].set_xscale("log", base=2)
    axes[0].set_yscale("log")
    axes[0].set_xlabel("--environment-directions K")
    axes[0].set_ylabel(f"relMSE vs path tracer ({VPLS} VPLs, seeds 1-3)")
    axes[0].grid(True, which="both", alpha=0.3)
    axes[0].legend()
    for scene in [s for s in dict.fromkeys(r["scene"] for r in rows if r["part"] == "portals")]:
        points = [r for r in rows if r["part"] == "portals" and r["scene"] == scene]
        axes[1].plot([r["portal_share"] for r in points], [r["relmse_median"] for r in points], marker="o", label=scene)
    axes[1].set_yscale("log")
    axes[1].set_xlabel("--portal-share")
    axes[1].set_ylabel(f"relMSE median over seeds 1-8 ({VPLS} VPLs)")
    axes[1].grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "sky.png", dpi=110)
    return out / "sky.png"


def main():
    build, work, out = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve(), Path(sys.argv[3]).resolve()
    parts = (sys.argv[4] if len(sys.argv) > 4 else ALL_PARTS).split(",")
    scenes_dir = Path(sys.argv[5]) if len(sys.argv) > 5 else Path(__file__).resolve().parents[3] / "shared" / "scenes"
    trees = int(sys.argv[6]) if len(sys.argv) > 6 else 300
    work.mkdir(parents=True, exist_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    if not (work / f"forest_{trees}.gltf").exists():
        generator = Path(__file__).resolve().parents[1] / "scenes" / "forest.py"
        subprocess.run([sys.executable, str(generator), str(trees), str(work)], check=True)
    lines = []

    def log(line):
        print(line, flush=True)
        lines.append(line)

    rows = []
    if "portals" in parts:
        rows += portals_part(build, work, scenes_dir, trees, ["window-sky", "blinds-sky", "two-windows", "sponza"], log)
    if "sun" in parts:
        rows += portals_part(build, work, scenes_dir, trees, ["window-sun"], log)
    if "clamp" in parts:  # the clamp's share of the rooms' darkness: no clamp, share 0 and 0.7
        rows += portals_part(build, work, scenes_dir, trees, ["window-sky", "blinds-sky", "two-windows", "window-sun"], log,
                             shares=[0.0, 0.7], extra=("--clamp", "0"), tag="clamp")
    if "converge" in parts:  # does the rooms' darkness go with more VPLs? 256 VPLs, shares 0 and 0.7, seeds 1-3
        rows += portals_part(build, work, scenes_dir, trees,
                             ["window-sky", "blinds-sky", "two-windows", "sponza", "window-sun"], log,
                             shares=[0.0, 0.7], tag="converge", vpls=256, seeds=[1, 2, 3])
    if "directions" in parts:
        rows += directions_part(build, work, scenes_dir, trees, log)
    if "samplers" in parts:  # is the image mean steady over seeds, with either sampler?
        for sampler in ("qmc", "importance"):
            rows += portals_part(build, work, scenes_dir, trees,
                                 ["window-sky", "blinds-sky", "two-windows", "window-sun", "window", "blinds"], log,
                                 shares=[0.7], extra=("--vpl-sampler", sampler), tag="samplers", seeds=list(range(1, 17)))
    suffix = "" if sorted(parts) == sorted(ALL_PARTS.split(",")) else "_" + "_".join(parts)
    write_csv(out / f"sky{suffix}.csv", rows)
    (out / f"sky{suffix}_findings.txt").write_text(
        "igi-render vs igi-path-render (pixel centres); the machine is shared (2 cores, others compiling): "
        "timings are noisy medians\n" + "\n".join(lines) + "\n")
    png = chart(out, rows) if any(r["part"] in ("directions", "portals") for r in rows) else None
    print(f"sky: wrote {out}/sky{suffix}.csv, sky{suffix}_findings.txt" + (f", {png}" if png else ""))


if __name__ == "__main__":
    main()
