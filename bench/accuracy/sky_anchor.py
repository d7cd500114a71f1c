"""The anchor of the sky-lit speed-against-accuracy chart: what users would pick instead of IGI,
igi's path tracer denoised by Intel Open Image Denoise (OIDN), against IGI at equal frame time.

Scenes: sky.py's window-lit rooms window-sky, blinds-sky, two-windows and Sponza.gltf under the
default sky (skipped, with a message, when SCENES_DIR/sponza is missing), at sky.py's SIZE, against
sky.py's cached references (sky.reference: the pixel-centre path tracer, 2 x REFERENCE_SPP).

  IGI         igi-render at its defaults, --temporal 0 (single independent frames), --vpls in VPLS,
              seeds IGI_SEEDS: relMSE (igi-compare --json) mean over the seeds; ms per frame the
              median ms_per_frame of one more run with --frames TIMED_FRAMES (as sky.py).
  path tracer igi-path-render --pixel-centre --aov at SPP, seeds PATH_SEEDS (not the references'
              1 and 2): the image, and the first hit's albedo and normal of the same pixel-centre
              rays. Time: the render's own seconds (its report line).
  PT+OIDN     that image denoised by OIDN's "RT" filter (hdr, albedo and normal given, cleanAux: the
              auxiliary images come from one noise-free ray per pixel). Time: the path tracer's
              plus OIDN's execute call (median of OIDN_REPEATS, timed here in Python, 2 threads).

Needs numpy and the PyPI package oidn (which ships the OIDN library) for the anchor; without them
it says so and measures IGI and the plain path tracer only. Timings are wall clock on a shared
2-core machine: noisy medians.

usage: python bench/accuracy/sky_anchor.py BUILD_DIR WORK_DIR OUT_DIR [SCENES_DIR] [SCENES]
  SCENES: comma-separated subset of window-sky,blinds-sky,two-windows,sponza (default: all)
writes OUT_DIR/sky_anchor.csv, sky_anchor_findings.txt and sky_anchor.png (if matplotlib imports);
its own images go to WORK_DIR as anchor_*.pfm.
"""

import ctypes
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sky  # noqa: E402  (the scenes, references and program runs of the sky benchmark)

SCENES = ["window-sky", "blinds-sky", "two-windows", "sponza"]  # sky.py's window-lit scenes under the sky
# IGI's curve: from below its interactive default (16) to 4x it, and on to 16x it, where its frame
# takes about as long as the path tracer's 1 spp plus OIDN: the two at equal time.
VPLS = [4, 8, 16, 32, 64, 128, 256]
IGI_SEEDS = [1, 2, 3]  # as sky.py's curves: enough for a mean, few enough for minutes
SPP = [1, 2, 4, 8, 16, 32]  # the anchor's curve: from its cheapest frame (1 spp) to 32x that
PATH_SEEDS = [101, 102, 103]  # not 1 or 2, the references' seeds, so that no sample is shared
OIDN_REPEATS = 3  # executions of the filter per image; the median is its time
OIDN_THREADS = 2  # the machine's cores, as igi-render and igi-path-render use (--threads 2)


class Denoiser:
    """OIDN's "RT" filter on shared numpy images of one size (committed once, as a renderer would)."""

    def __init__(self, oidn, numpy, width, height):
        self.oidn, self.numpy = oidn, numpy
        # The package binds only some of OIDN's C API; the parameters (hdr, cleanAux, numThreads)
        # and error messages come from the library it loaded.
        library = vars(oidn).get("__lib_oidn")
        if library is None:
            raise RuntimeError("oidn: the package's loaded library (oidn.__lib_oidn) is not there")
        self.set_filter_bool = library.oidnSetFilter1b
        self.set_filter_bool.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_bool]
        self.set_filter_bool.restype = None
        set_device_int = library.oidnSetDevice1i
        set_device_int.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
        set_device_int.restype = None
        self.device_error = library.oidnGetDeviceError
        self.device_error.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_char_p)]
        self.device_error.restype = ctypes.c_int
        self.device = oidn.NewDevice(oidn.DEVICE_TYPE_CPU)
        set_device_int(self.device, b"numThreads", OIDN_THREADS)
        oidn.CommitDevice(self.device)
        self.check("device")
        shape = (height, width, 3)
        self.color, self.albedo, self.normal, self.output = (numpy.zeros(shape, numpy.float32) for _ in range(4))
        self.filter = oidn.NewFilter(self.device, "RT")
        for name, image in (("color", self.color), ("albedo", self.albedo), ("normal", self.normal),
                            ("output", self.output)):
            oidn.SetSharedFilterImage(self.filter, name, image, oidn.FORMAT_FLOAT3, width, height)
        self.set_filter_bool(self.filter, b"hdr", True)
        self.set_filter_bool(self.filter, b"cleanAux", True)
        start = time.perf_counter()
        oidn.CommitFilter(self.filter)
        self.commit_ms = 1000 * (time.perf_counter() - start)
        self.check("filter")

    def check(self, what):
        message = ctypes.c_char_p()
        if self.device_error(self.device, ctypes.byref(message)) != 0:
            raise RuntimeError(f"oidn {what}: {message.value.decode() if message.value else 'error'}")

    def denoise(self, color, albedo, normal):
        """The denoised image (a copy) and the median milliseconds of OIDN_REPEATS executions."""
        numpy = self.numpy
        numpy.copyto(self.color, color)
        numpy.copyto(self.albedo, numpy.clip(albedo, 0.0, 1.0))  # OIDN reads albedo in [0, 1]
        numpy.copyto(self.normal, numpy.clip(normal, -1.0, 1.0))
        milliseconds = []
        for _ in range(OIDN_REPEATS):
            start = time.perf_counter()
            self.oidn.ExecuteFilter(self.filter)
            milliseconds.append(1000 * (time.perf_counter() - start))
        self.check("execute")
        return self.output.copy(), statistics.median(milliseconds)

    def release(self):
        self.oidn.ReleaseFilter(self.filter)
        self.oidn.ReleaseDevice(self.device)


def load_oidn():
    """(oidn, numpy) or (None, why not)."""
    try:
        import numpy
        import oidn
    except ImportError as error:
        return None, f"{error} (pip install numpy oidn)"
    return (oidn, numpy), ""


def read_image(numpy, path):
    width, height, values = sky.read_pfm(path)
    return numpy.frombuffer(values.tobytes(), dtype=numpy.float32).reshape(height, width, 3)


def best_within(points, budget):
    """The least relMSE among `points` (ms, relMSE) at most `budget` ms, or None."""
    errors = [error for ms, error in points if ms <= budget]
    return min(errors) if errors else None


def winning_budgets(igi, anchor):
    """The budgets (every point's ms) and who has less error within each: IGI, anchor or neither."""
    verdicts = []
    for budget in sorted({ms for ms, _ in igi + anchor}):
        mine, theirs = best_within(igi, budget), best_within(anchor, budget)
        if mine is None and theirs is None:
            continue
        winner = "IGI" if theirs is None or (mine is not None and mine < theirs) else "PT+OIDN"
        verdicts.append((budget, mine, theirs, winner))
    return verdicts


def describe_wins(verdicts):
    """Who wins over which budgets, as segments: "IGI below 228 ms, PT+OIDN from 228 ms": a winner
    holds from its first measured budget until the next winner's."""
    segments = []
    for budget, _, _, winner in verdicts:
        if not segments or segments[-1][0] != winner:
            segments.append((winner, budget))
    words = []
    for index, (winner, budget) in enumerate(segments):
        following = segments[index + 1][1] if index + 1 < len(segments) else None
        if index == 0 and following is not None:
            words.append(f"{winner} below {following:.0f} ms")
        elif index == 0:
            words.append(f"{winner} at every measured budget")
        elif following is None:
            words.append(f"{winner} from {budget:.0f} ms")
        else:
            words.append(f"{winner} from {budget:.0f} to {following:.0f} ms")
    return ", ".join(words)


def scene_part(build, work, scenes_dir, scene, denoiser_tools, log):
    arguments = sky.scene_arguments(scene, scenes_dir, work, 0)
    ref, noise, ref_mean = sky.reference(build, work, scene, arguments)
    log(f"\n[{scene}] {sky.SIZE}; reference {2 * sky.REFERENCE_SPP} spp pixel-centre path tracer "
        f"(seed 1 vs 2 relMSE {noise:.4f}; its average's own noise about a quarter), mean {ref_mean:.4f}")
    rows = []
    log(f"  IGI (--temporal 0), seeds {IGI_SEEDS[0]}-{IGI_SEEDS[-1]}")
    log(f"  {'VPLs':>5} {'relMSE mean':>11} {'median':>7} {'max':>8} {'ms/frame':>9}")
    for vpls in VPLS:
        errors = []
        for seed in IGI_SEEDS:
            test = work / f"anchor_{scene}_igi{vpls}_s{seed}.pfm"
            sky.render(build, arguments + ["--vpls", str(vpls), "--seed", str(seed)], test)
            errors.append(sky.compare(build, ref, test)["relmse"])
        timing = sky.render(build, arguments + ["--vpls", str(vpls), "--frames", str(sky.TIMED_FRAMES)],
                            work / "anchor_timing.pfm")
        rows.append({"scene": scene, "method": "IGI", "setting": f"{vpls} VPLs", "vpls": vpls, "spp": "",
                     "seeds": len(errors), "relmse_mean": statistics.mean(errors),
                     "relmse_median": statistics.median(errors), "relmse_max": max(errors),
                     "relmse_per_seed": " ".join(f"{e:.4f}" for e in errors), "ms_per_frame": timing["ms_per_frame"],
                     "reference_noise_relmse": noise})
        log(f"  {vpls:5} {rows[-1]['relmse_mean']:11.4f} {rows[-1]['relmse_median']:7.4f} {max(errors):8.4f} "
            f"{timing['ms_per_frame']:9.1f}")
    denoiser = None
    if denoiser_tools:
        oidn, numpy = denoiser_tools
        width, height = (int(n) for n in sky.SIZE.split("x"))
        denoiser = Denoiser(oidn, numpy, width, height)
    log(f"  path tracer (pixel centres), seeds {PATH_SEEDS[0]}-{PATH_SEEDS[-1]}" +
        (f"; + OIDN RT (hdr, albedo, normal, cleanAux; commit {denoiser.commit_ms:.0f} ms once)" if denoiser else ""))
    log(f"  {'spp':>5} {'PT relMSE':>9} {'PT ms':>8} {'+OIDN relMSE':>12} {'median':>7} {'max':>8} {'OIDN ms':>8} "
        f"{'PT+OIDN ms':>10}")
    for spp in SPP:
        plain, denoised, path_ms, oidn_ms, first_hit_ms = [], [], [], [], []
        for seed in PATH_SEEDS:
            test = work / f"anchor_{scene}_pt{spp}_s{seed}.pfm"
            path_ms.append(1000 * sky.path_render(build, arguments + ["--aov"], test, spp, seed))
            plain.append(sky.compare(build, ref, test)["relmse"])
            if denoiser:
                image, ms = denoiser.denoise(read_image(numpy, test),
                                             read_image(numpy, test.with_name(f"{test.stem}_albedo.pfm")),
                                             read_image(numpy, test.with_name(f"{test.stem}_normal.pfm")))
                oidn_ms.append(ms)
                clean = test.with_name(f"{test.stem}_oidn.pfm")
                sky.write_pfm(clean, width, height, image)
                denoised.append(sky.compare(build, ref, clean)["relmse"])
        ms = statistics.median(path_ms)
        rows.append({"scene": scene, "method": "path tracer", "setting": f"{spp} spp", "vpls": "", "spp": spp,
                     "seeds": len(plain), "relmse_mean": statistics.mean(plain),
                     "relmse_median": statistics.median(plain), "relmse_max": max(plain),
                     "relmse_per_seed": " ".join(f"{e:.4f}" for e in plain), "ms_per_frame": ms,
                     "reference_noise_relmse": noise})
        line = f"  {spp:5} {rows[-1]['relmse_mean']:9.4f} {ms:8.1f}"
        if denoiser:
            total = [p + o for p, o in zip(path_ms, oidn_ms)]
            rows.append({"scene": scene, "method": "PT+OIDN", "setting": f"{spp} spp + OIDN", "vpls": "", "spp": spp,
                         "seeds": len(denoised), "relmse_mean": statistics.mean(denoised),
                         "relmse_median": statistics.median(denoised), "relmse_max": max(denoised),
                         "relmse_per_seed": " ".join(f"{e:.4f}" for e in denoised),
                         "ms_per_frame": statistics.median(total), "path_ms": ms,
                         "oidn_ms": statistics.median(oidn_ms), "oidn_commit_ms": denoiser.commit_ms,
                         "reference_noise_relmse": noise})
            line += (f" {rows[-1]['relmse_mean']:12.4f} {rows[-1]['relmse_median']:7.4f} {max(denoised):8.4f} "
                     f"{rows[-1]['oidn_ms']:8.1f} {rows[-1]['ms_per_frame']:10.1f}")
        log(line)
    if denoiser:
        denoiser.release()
        for statistic in ("relmse_mean", "relmse_median"):
            igi = [(r["ms_per_frame"], r[statistic]) for r in rows if r["method"] == "IGI"]
            anchor = [(r["ms_per_frame"], r[statistic]) for r in rows if r["method"] == "PT+OIDN"]
            best = min((r for r in rows if r["method"] == "IGI"), key=lambda r: r[statistic])
            fastest = min((r for r in rows if r["method"] == "PT+OIDN"), key=lambda r: r["ms_per_frame"])
            log(f"  {statistic.replace('relmse_', 'relMSE ')}: IGI's least {best[statistic]:.4f} ({best['setting']}, "
                f"{best['ms_per_frame']:.0f} ms) against PT+OIDN's fastest frame {fastest[statistic]:.4f} "
                f"({fastest['setting']}, {fastest['ms_per_frame']:.0f} ms)")
            log(f"  less error within a frame budget ({statistic.replace('relmse_', 'relMSE ')} over seeds, the "
                f"least of the settings that fit): {describe_wins(winning_budgets(igi, anchor))}")
    return rows


def file_pyplot():
    """matplotlib's pyplot drawing into files (no display here), or None without matplotlib."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg")
    import matplotlib.pyplot
    return matplotlib.pyplot


def chart(out, rows):
    plt = file_pyplot()
    if plt is None:
        return None
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    columns = min(2, len(scenes))  # two panels a row: wide enough to read a log axis's labels
    panel_rows = (len(scenes) + columns - 1) // columns
    # Inches per panel: room for the legend and the points' labels at the saved resolution.
    figure, axes = plt.subplots(panel_rows, columns, figsize=(5.5 * columns, 4.2 * panel_rows), squeeze=False)
    # One time axis for every panel, so that the scenes' frame times compare at a glance.
    times = [r["ms_per_frame"] for r in rows]
    span = (min(times) / 1.5, max(times) * 1.5)  # a margin of half a point's value on each side
    styles = {"IGI": ("o", "tab:blue"), "PT+OIDN": ("s", "tab:red"), "path tracer": ("^", "tab:gray")}
    for axis, scene in zip(axes.flat, scenes):
        for method, (marker, colour) in styles.items():
            points = [r for r in rows if r["scene"] == scene and r["method"] == method]
            if not points:
                continue
            axis.plot([r["ms_per_frame"] for r in points], [r["relmse_mean"] for r in points], marker=marker,
                      color=colour, label=method, linestyle=":" if method == "path tracer" else "-")
            for r in points:
                axis.annotate(str(r["vpls"] or r["spp"]), (r["ms_per_frame"], r["relmse_mean"]), fontsize=6,
                              textcoords="offset points", xytext=(3, 3), color=colour)
        floor = [r["reference_noise_relmse"] / 4 for r in rows if r["scene"] == scene][0]
        axis.axhline(floor, color="black", linewidth=0.7, linestyle="--", label="reference's own noise (est.)")
        axis.set_xscale("log")
        axis.set_xlim(*span)
        axis.set_yscale("log")
        axis.set_title(scene)
        axis.set_xlabel("ms per frame (320x240, 2 threads)")
        axis.grid(True, which="both", alpha=0.3)
    for axis in axes[:, 0]:
        axis.set_ylabel("relMSE vs reference (mean over 3 seeds)")
    for axis in axes.flat[len(scenes):]:
        axis.set_visible(False)
    axes[0][0].legend(fontsize=7)
    figure.suptitle("IGI (labels: VPLs) against the path tracer and PT+OIDN (labels: spp)", fontsize=9)
    figure.tight_layout()
    figure.savefig(out / "sky_anchor.png", dpi=110)
    return out / "sky_anchor.png"


def write_results(out, rows, lines):
    """The findings text, the CSV and (with matplotlib) the chart into `out`; the paths written."""
    findings = out / "sky_anchor_findings.txt"
    findings.write_text("IGI (igi-render --temporal 0) against igi-path-render --pixel-centre, plain and denoised by "
                        "OIDN; the machine is shared (2 cores, others compiling): timings are noisy medians\n" +
                        "\n".join(lines) + "\n")
    sky.write_csv(out / "sky_anchor.csv", rows)
    return [str(path) for path in (findings, out / "sky_anchor.csv", chart(out, rows)) if path]


def main():
    build, work, out = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve(), Path(sys.argv[3]).resolve()
    scenes_dir = Path(sys.argv[4]) if len(sys.argv) > 4 else Path(__file__).resolve().parents[3] / "shared" / "scenes"
    scenes = sys.argv[5].split(",") if len(sys.argv) > 5 else SCENES
    work.mkdir(parents=True, exist_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    lines = []

    def log(line):
        print(line, flush=True)
        lines.append(line)

    tools, why_not = load_oidn()
    if tools is None:
        log(f"sky_anchor: no OIDN anchor, {why_not}: measuring IGI and the plain path tracer only")
    else:
        log(f"sky_anchor: OIDN {tools[0].oidn_version} from the oidn package {tools[0].oidn_py_version} "
            f"({Path(tools[0].__file__).parent})")
    rows = []
    for scene in scenes:
        if scene == "sponza" and not (Path(scenes_dir) / "sponza" / "Sponza.gltf").exists():
            log(f"\nsky_anchor: SKIPPED sponza: {Path(scenes_dir) / 'sponza' / 'Sponza.gltf'} is missing "
                f"(pass SCENES_DIR, the folder of the shared scenes)")
            continue
        rows += scene_part(build, work, scenes_dir, scene, tools, log)
    oidn_ms = [r["oidn_ms"] for r in rows if r["method"] == "PT+OIDN"]
    if oidn_ms:
        log(f"\nOIDN RT at {sky.SIZE}, {OIDN_THREADS} threads: execute median {statistics.median(oidn_ms):.0f} ms per "
            f"frame ({min(oidn_ms):.0f}-{max(oidn_ms):.0f} ms over the {len(oidn_ms)} scene x spp medians)")
    print("sky_anchor: wrote " + ", ".join(write_results(out, rows, lines)))

if __name__ == "__main__":
    main()
