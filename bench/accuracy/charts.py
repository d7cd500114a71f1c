"""Charts of one scene's accuracy sweep (rows as sweep.py writes them to accuracy_<scene>.csv).

accuracy_<scene>_time.png: error against time per frame, log-log, one curve per method (IGI
interleaving x filter, anti-aliasing 4, no clamp, and the path tracer over spp): RMSE over all
pixels, RMSE off the visible luminaire and relMSE against CPU time, and RMSE off the luminaire
against wall-clock time.
accuracy_<scene>_vpls.png: IGI's RMSE off the luminaire against VPLs per pixel and against the
clamp distance, and the path tracer's RMSE against spp beside the 1/sqrt(spp) line through its
first point.
Usable on its own (charts and the printed findings): python3 charts.py bench/results/accuracy_cornell.csv [...]
"""

import csv
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

# Colour per interleaving (and the path tracer), line style per filter.
COLOURS = {1: "tab:grey", 3: "tab:blue", 5: "tab:purple"}
STYLES = {"none": ":", "box": "--", "discontinuity": "-"}
PATH_COLOUR = "black"


def curves(rows):
    """Method label -> its rows in increasing cost, in the order the methods first appear."""
    out = {}
    for row in rows:
        if row["sweep"] == "clamp":
            continue
        out.setdefault(row["method"], []).append(row)
    for label in out:
        out[label].sort(key=lambda r: float(r["ms_per_frame"]))
    return out


def style(row):
    """Matplotlib keywords for the curve `row` belongs to."""
    if row["integrator"] == "path":
        return {"color": PATH_COLOUR, "linestyle": "-", "marker": "s", "linewidth": 2.2}
    if row["sweep"] == "aa":
        return {"color": "tab:green", "linestyle": "-", "marker": "^"}
    if row["sweep"] == "clamp_off":
        return {"color": "tab:red", "linestyle": "-", "marker": "v"}
    return {"color": COLOURS[int(row["interleave"])], "linestyle": STYLES[row["filter"]], "marker": "o", "markersize": 3.5}


def error(row, metric):
    """The charted error: an RMSE less the reference's own noise, relMSE, or 1 - SSIM."""
    if metric == "rmse":
        return float(row["rmse_minus_reference_noise"])
    if metric == "rmse_outside":
        return float(row["rmse_outside_luminaire_minus_reference_noise"])
    if metric == "ssim":
        return 1.0 - float(row["ssim"])
    return float(row[metric])


METRIC_LABELS = {"rmse": "RMSE, all pixels (reference noise removed)",
                 "rmse_outside": "RMSE off the visible luminaire (reference noise removed)",
                 "relmse": "relMSE", "ssim": "1 - SSIM"}
TIME_LABELS = {"cpu_ms_per_frame": "CPU ms per frame (both threads' time; little disturbed by the load)",
               "ms_per_frame": "wall-clock ms per frame (median)"}


def reference_note(rows):
    """Title fragment naming the reference and the machine's load."""
    first = rows[0]
    loads = sorted(float(r["load_before"]) for r in rows)
    return (f"reference {first['reference_spp']} spp path-traced (its own noise RMSE {float(first['reference_noise_rmse']):.4f}, "
            f"{float(first['reference_noise_rmse_outside_luminaire']):.4f} off the luminaire); "
            f"load average {loads[0]:.1f}-{loads[-1]:.1f} on 2 cores")


def reference_noise_line(axis, rows, metric):
    """A horizontal line at the reference's own noise (already removed from the charted RMSE)."""
    key = {"rmse": "reference_noise_rmse", "rmse_outside": "reference_noise_rmse_outside_luminaire"}.get(metric)
    if key:
        axis.axhline(float(rows[0][key]), color="0.6", linewidth=1, linestyle="-.", label="reference's own noise (removed)")


def error_against_time(axis, by_method, metric, time_key):
    """One panel: `metric` against `time_key` for every method."""
    for label, points in by_method.items():
        # A run shorter than the CPU clock's tick less set-up shows 0 CPU ms: left out of log axes.
        points = sorted((p for p in points if float(p[time_key]) > 0.0), key=lambda r: float(r[time_key]))
        if not points:
            continue
        # An error of exactly 0 (identical images) would vanish from a log axis: 1e-6 is far below any measured.
        axis.plot([float(p[time_key]) for p in points], [max(error(p, metric), 1e-6) for p in points],
                  label=label, **style(points[0]))
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_xlabel(TIME_LABELS[time_key])
    axis.set_ylabel(METRIC_LABELS[metric])
    axis.grid(True, which="both", alpha=0.3)


def draw(rows, results, scene):
    """Writes the two charts of `scene` into `results`."""
    rows = [r for r in rows if r["scene"] == scene]
    by_method = curves(rows)
    figure, axes = plt.subplots(2, 2, figsize=(15, 11))
    panels = (("rmse", "cpu_ms_per_frame"), ("rmse_outside", "cpu_ms_per_frame"),
              ("relmse", "cpu_ms_per_frame"), ("rmse_outside", "ms_per_frame"))
    for axis, (metric, time_key) in zip(axes.flat, panels):
        error_against_time(axis, by_method, metric, time_key)
        reference_noise_line(axis, rows, metric)
    axes[0, 0].legend(fontsize=8, loc="lower left")
    figure.suptitle(f"{scene}, 640x480: error against time; IGI points are 1..256 VPLs per pixel, "
                    f"path tracer 1..{max(int(r['spp']) for r in rows if r['integrator'] == 'path')} spp\n"
                    f"{reference_note(rows)}", fontsize=10)
    figure.tight_layout()
    figure.savefig(results / f"accuracy_{scene}_time.png", dpi=80)
    plt.close(figure)

    figure, axes = plt.subplots(1, 3, figsize=(19, 6.2))
    axis = axes[0]
    for label, points in by_method.items():
        if points[0]["integrator"] == "path":
            continue
        points = sorted(points, key=lambda r: float(r["vpls_per_set"]))
        axis.plot([float(p["vpls_per_set"]) for p in points], [error(p, "rmse_outside") for p in points],
                  label=label, **style(points[0]))
    reference_noise_line(axis, rows, "rmse_outside")
    axis.set_xscale("log", base=2)
    axis.set_yscale("log")
    axis.set_xlabel("VPLs per pixel: the mean size of one interleaving set (requested M = 1..256)")
    axis.set_ylabel(METRIC_LABELS["rmse_outside"])
    axis.set_title("IGI: error against VPL count")
    axis.legend(fontsize=7.5, loc="lower left")

    axis = axes[1]
    clamp_rows = [r for r in rows if r["integrator"] == "igi" and r["sweep"] in ("clamp", "clamp_off", "main")
                  and r["interleave"] == "3" and r["filter"] == "discontinuity" and r["aa"] == "1"]
    for vpls, marker in (("16", "o"), ("256", "s")):
        points = sorted((r for r in clamp_rows if r["vpls_per_pixel"] == vpls), key=lambda r: float(r["clamp_factor"]))
        axis.plot([float(p["clamp_factor"]) for p in points], [error(p, "rmse_outside") for p in points],
                  marker=marker, label=f"M = {vpls} VPLs per pixel")
    axis.set_xscale("symlog", linthresh=0.25)  # 0 (no clamp) sits on the linear part
    axis.set_yscale("log")
    axis.set_xlabel("clamp distance / automatic (2% of the scene diagonal); 0 = no clamp")
    axis.set_ylabel(METRIC_LABELS["rmse_outside"])
    axis.set_title("IGI 3x3 discontinuity: error against the clamp")
    axis.legend(fontsize=8)

    axis = axes[2]
    path = sorted((r for r in rows if r["integrator"] == "path"), key=lambda r: int(r["spp"]))
    if path:
        spp = [int(p["spp"]) for p in path]
        axis.plot(spp, [error(p, "rmse") for p in path], color=PATH_COLOUR, marker="s", label="path tracer")
        first = error(path[0], "rmse") * spp[0] ** 0.5
        axis.plot(spp, [first / s ** 0.5 for s in spp], color="0.5", linestyle="--", label="1/sqrt(spp) through 1 spp")
    axis.set_xscale("log", base=2)
    axis.set_yscale("log")
    axis.set_xlabel("samples per pixel")
    axis.set_ylabel(METRIC_LABELS["rmse"])
    axis.set_title("path tracer: error against spp")
    axis.legend(fontsize=8)
    for axis in axes:
        axis.grid(True, which="both", alpha=0.3)
    figure.suptitle(f"{scene}: error against VPLs, clamp and spp. {reference_note(rows)}", fontsize=10)
    figure.tight_layout()
    figure.savefig(results / f"accuracy_{scene}_vpls.png", dpi=80)
    plt.close(figure)
    print(f"  wrote {results / f'accuracy_{scene}_time.png'} and {results / f'accuracy_{scene}_vpls.png'}", flush=True)


def findings(rows, scene, time_key="cpu_ms_per_frame"):
    """Prints, per metric and per path-tracer run (a time budget), the best IGI run costing no
    more, IGI's lowest error overall, and the path tracer's slope of log RMSE against log spp
    (-0.5 for 1/sqrt(spp)). Returns the text."""
    rows = [r for r in rows if r["scene"] == scene and float(r[time_key]) > 0.0]
    path = sorted((r for r in rows if r["integrator"] == "path"), key=lambda r: float(r[time_key]))
    igi = [r for r in rows if r["integrator"] == "igi"]
    lines = [f"{scene}, time = {time_key}:"]
    for metric in ("rmse", "rmse_outside", "relmse"):
        lines.append(f"  {metric}: budget (path tracer spp, ms): path tracer error / best IGI within the budget")
        for p in path:
            budget = float(p[time_key])
            affordable = [r for r in igi if float(r[time_key]) <= budget]
            if not affordable:
                lines.append(f"    {p['spp']:>3} spp, {budget:8.0f} ms: {error(p, metric):.4g} / no IGI run that fast")
                continue
            best = min(affordable, key=lambda r: error(r, metric))
            verdict = "IGI" if error(best, metric) < error(p, metric) else "path"
            lines.append(f"    {p['spp']:>3} spp, {budget:8.0f} ms: {error(p, metric):.4g} / {error(best, metric):.4g} "
                         f"({best['run']}, {float(best[time_key]):.0f} ms): {verdict} lower")
        fastest = min(igi, key=lambda r: float(r[time_key]))
        best = min(igi, key=lambda r: error(r, metric))
        lines.append(f"    IGI's fastest run {fastest['run']} {float(fastest[time_key]):.0f} ms: {error(fastest, metric):.4g}; "
                     f"IGI's lowest {error(best, metric):.4g} ({best['run']}, {float(best[time_key]):.0f} ms)")
    spp = [math.log(int(p["spp"])) for p in path]
    rmse = [math.log(max(error(p, "rmse"), 1e-9)) for p in path]
    mean_spp, mean_rmse = sum(spp) / len(spp), sum(rmse) / len(rmse)
    slope = (sum((a - mean_spp) * (b - mean_rmse) for a, b in zip(spp, rmse)) /
             sum((a - mean_spp) ** 2 for a in spp))
    lines.append(f"  path tracer: slope of log RMSE against log spp {slope:.3f} (1/sqrt(spp): -0.5)")
    text = "\n".join(lines)
    print(text, flush=True)
    return text


def main():
    for name in sys.argv[1:]:
        path = Path(name)
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        draw(rows, path.parent, rows[0]["scene"])
        findings(rows, rows[0]["scene"])


if __name__ == "__main__":
    main()
