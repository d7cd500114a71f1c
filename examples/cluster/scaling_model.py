#!/usr/bin/env python3
"""Scaling MODEL of the igi tile farm from one machine's measurements (measure_cluster.sh output).

This is a model, not a measurement: it takes the measured per-tile render cost, the measured
per-frame fixed cost (VPL generation, replicated on every worker) and the measured bytes per
frame, and projects frames per second for N workers on 1 Gbit/s Ethernet, where rank 0's link
caps the frame rate at link_bytes_per_second / bytes_per_frame.

    t(N)   = t_fixed + tiles * (t_tile + t_overhead + rtt) / N          (ms per frame)
    fps(N) = min(1000 / t(N), link / bytes_per_frame)

Usage: scaling_model.py MEASURE_DIR [chart.png]   (the chart needs matplotlib; optional)
"""
import json
import statistics
import sys

LINK_BYTES_PER_SECOND = 125e6  # 1 Gbit/s, the paper's server uplink
# Assumed MPI round trip per tile request on switched Gigabit Ethernet (a worker idles for it):
# ~100 microseconds is typical of TCP MPI latency there; it is an assumption, not measured here.
RTT_MS = 0.1
WORKERS = [1, 2, 4, 8, 16, 24, 48, 96]


def steady(run, key):
    """Median of a per-frame value over frames >= 1 (frame 0 also ships HDR for its own tone mapping)."""
    frames = run["frames"][1:] or run["frames"]
    return statistics.median(f[key] for f in frames)


def main():
    folder = sys.argv[1]
    runs = {np: json.load(open(f"{folder}/np{np}.json")) for np in (1, 2, 3)}
    tiles = runs[2]["tiles"]
    ms = {np: steady(runs[np], "ms") for np in runs}
    tile_sum = {np: steady(runs[np], "tile_ms_sum") for np in runs}
    t_tile = tile_sum[2] / tiles
    t_fixed = max(ms[1] - tile_sum[1], 0.0)
    t_overhead = max((ms[2] - t_fixed - tile_sum[2]) / tiles, 0.0)
    bytes_per_frame = steady(runs[3], "bytes_to_master")
    pixel_bytes = steady(runs[3], "pixel_bytes")
    cap = LINK_BYTES_PER_SECOND / bytes_per_frame
    print(f"measured: {runs[2]['width']}x{runs[2]['height']}, {tiles} tiles of {runs[2]['tile_size']} px")
    print(f"measured: frame ms alone {ms[1]:.1f}, 1 worker {ms[2]:.1f}, 2 workers {ms[3]:.1f}; "
          f"speed-up 1->2 workers {ms[2] / ms[3]:.2f}x")
    print(f"measured: per-tile render {t_tile:.3f} ms, fixed per frame {t_fixed:.1f} ms, "
          f"per-tile farm overhead {t_overhead:.3f} ms")
    print(f"measured: bytes to rank 0 per frame {bytes_per_frame:.0f} (pixels {pixel_bytes:.0f}, "
          f"{bytes_per_frame / tiles:.0f} per tile); 1 Gbit/s cap {cap:.1f} fps")
    rows = []
    for n in WORKERS:
        t = t_fixed + tiles * (t_tile + t_overhead + RTT_MS) / n
        compute = 1000.0 / t
        rows.append((n, compute, min(compute, cap), compute > cap))
    print("MODEL (not measured): workers, compute-bound fps, fps with the 1 Gbit/s cap, link-bound?")
    for n, compute, fps, bound in rows:
        print(f"  {n:3d}  {compute:8.1f}  {fps:8.1f}  {'link' if bound else 'compute'}")
    per_tile = t_tile + t_overhead + RTT_MS
    if t_fixed > 0:
        print(f"MODEL: as N grows, fps approaches 1000 / t_fixed = {1000.0 / t_fixed:.0f} (VPLs are built on every worker)")
    print(f"MODEL: the link saturates first at N = {cap * tiles * per_tile / 1000.0:.0f} workers if the fixed cost "
          f"were hidden (pipelined with the previous frame); with it, "
          + ("never" if t_fixed >= 1000.0 / cap else
             f"at N = {tiles * per_tile / (1000.0 / cap - t_fixed):.0f}"))
    if len(sys.argv) > 2:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        ax.plot([r[0] for r in rows], [r[1] for r in rows], "--", color="grey", label="model: compute only")
        ax.plot([r[0] for r in rows], [r[2] for r in rows], "o-", label="model: with 1 Gbit/s link at rank 0")
        base = rows[0][1]
        ax.plot([1, 48], [base, 48 * base], ":", color="green", label="linear (paper Fig. 6 shape, to 48 CPUs)")
        ax.plot([1, 2], [1000.0 / ms[2], 1000.0 / ms[3]], "s", color="red", label="measured here (1, 2 workers)")
        ax.axhline(cap, color="orange", lw=0.8, label=f"link cap {cap:.0f} fps")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("worker ranks (1 thread each)")
        ax.set_ylabel("frames per second")
        ax.set_title(f"igi tile farm, {runs[2]['width']}x{runs[2]['height']} {runs[2]['scene']}: MODEL")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(sys.argv[2], dpi=110)
        print(f"wrote {sys.argv[2]}")


if __name__ == "__main__":
    main()
