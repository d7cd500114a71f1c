#!/usr/bin/env python3
"""Turns bench/results/*.json (Google Benchmark output of pipeline_bench, scaling_bench,
shading_bench) into the tables between the marker comments of bench/README.md and PNG charts.

    python3 bench/report.py RESULTS_DIR README [--charts]

Tables are written between `<!-- bench:NAME -->` and `<!-- /bench:NAME -->`; everything else in
the README is left as it is. A missing result file leaves its table's old text in place.
Charts need matplotlib (run_all.sh makes a venv with it); without --charts none are drawn.
"""

import json
import math
import pathlib
import re
import sys

# The paper's numbers (Benthin, Wald, Slusallek 2003), AthlonMP 1800+, Mrays/s per CPU.
# Table 1, 1024x1024: (SSE none, SSE simple, non-SSE simple); Shirley-6 and Conference.
PAPER_TABLE1 = {
    ("cornell", "static"): (3.7, 1.55, 0.9),     # Shirley-6 (static)
    ("cornell", "dynamic"): (2.54, 1.29, 0.7),   # Shirley-6 (dynamic)
    ("sponza_lit", "static"): (2.5, 1.25, 0.77),  # Conference (static)
    ("sponza_lit", "dynamic"): (1.7, 1.0, 0.58),  # Conference (dynamic)
}
# Table 3, 16 VPLs, full shading and filtering: Office and Conference, static (dynamic).
PAPER_TABLE3 = {
    "640x480": {"office": (1.72, 1.41), "conference": (1.12, 0.85)},
    "800x600": {"office": (1.77, 1.45), "conference": (1.22, 0.94)},
    "1000x1000": {"office": (1.84, 1.49), "conference": (1.33, 1.03)},
    "1600x1200": {"office": (2.00, 1.63), "conference": (1.46, 1.09)},
}
# Section 4: "up to 20 fps at video resolution, and still 8 fps at full screen (1024x1024) with
# 12 VPLs per pixel" on 24 PCs / 48 CPUs.
PAPER_FPS = {"640x480": 20.0, "1024x1024": 8.0}

SCENES = ("cornell", "sponza_lit")


def load(results):
    """name -> benchmark record, over every *.json in `results` (suffixes Google Benchmark adds removed)."""
    records = {}
    for path in sorted(pathlib.Path(results).glob("*.json")):
        try:
            data = json.loads(path.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError):
            continue
        if not isinstance(data, dict) or "benchmarks" not in data:
            continue
        for b in data["benchmarks"]:
            name = re.sub(r"(/iterations:\d+)?(/manual_time)?(/real_time)?$", "", b.get("run_name", b["name"]))
            if b.get("error_occurred"):
                b = dict(b, skipped=b.get("error_message", "skipped"))
            if b.get("aggregate_name") not in (None, "median"):
                continue
            records[name] = b
    return records


def fmt(value, digits=2):
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if isinstance(value, float) and value.is_integer() and abs(value) >= 1:
        value = int(value)
    if isinstance(value, int):
        return f"{value:,}"
    if value == 0:
        return "0"
    if abs(value) >= 100:
        return f"{value:,.0f}"
    return f"{value:.{digits}f}"


def get(records, name, counter):
    b = records.get(name)
    if b is None or "skipped" in b:
        return None
    return b.get(counter)


def name_field(name, key):
    """The value of `key:VALUE` in a benchmark's name ("efficiency/cornell/vpls:12/threads:2", "vpls"
    gives "12"), or "—" when the name has none."""
    for part in name.split("/"):
        if part.startswith(key + ":"):
            return part.split(":", 1)[1]
    return "—"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(fmt(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def efficiency_table(r):
    rows = []
    for name in sorted(k for k in r if k.startswith("efficiency/")):
        scene, vpls, threads = name.split("/")[1], name_field(name, "vpls"), name_field(name, "threads")
        g = lambda c: get(r, name, c)
        rows.append([scene, vpls, threads, g("pipeline_ms"), g("embree_ms"), g("efficiency"), g("efficiency_cpu"),
                     g("ceiling_ms"), g("efficiency_ceiling"), g("layout_cost"), g("ceiling_build_ms"),
                     g("ceiling_shadow_leaks"), g("ceiling_shadow_extra_blocks"),
                     g("embree_closest_ms"), g("embree_occlusion_ms"), g("embree_single_ms"), g("setup_ms"),
                     g("lanes_per_closest_packet"), g("lanes_per_occlusion_packet"), g("recorded_rays"),
                     g("cpu_share")])
    if not rows:
        return None
    return table(["scene", "VPLs / pixel", "threads", "frame ms", "Embree alone ms", "**efficiency**", "efficiency by CPU time",
                  "ceiling ms", "**efficiency against the ceiling**", "igi layout / ceiling", "ceiling build ms",
                  "shadow rays leaking in the ceiling", "shadow rays blocked only in the ceiling",
                  "Embree: primary + secondary ms", "Embree: shadow ms", "Embree: VPL walks ms", "frame set-up ms",
                  "lanes / closest packet", "lanes / shadow packet", "rays", "CPU share"], rows)


def table1(r):
    rows = []
    for scene in SCENES:
        for mode in ("static", "dynamic"):
            ours = [get(r, f"table1/{scene}/{mode}/{k}", "mrays_per_cpu_s") for k in ("packet_cast", "packet_shaded", "single_shaded")]
            if all(v is None for v in ours):
                continue
            paper = PAPER_TABLE1[(scene, mode)]
            paper_name = {"cornell": "Shirley-6", "sponza_lit": "Conference"}[scene]
            ratio = ours[1] / ours[2] if ours[1] and ours[2] else None
            rows.append([f"{scene} ({mode})", ours[0], ours[1], ours[2], ratio,
                         f"{paper_name}: {paper[0]} / {paper[1]} / {paper[2]}"])
    if not rows:
        return None
    return table(["scene", "packet, no shading", "packet, simple shading", "single ray, simple shading",
                  "packet / single (shaded)", "paper: same three"], rows)


def table3(r):
    rows = []
    for size in PAPER_TABLE3:
        row = [size]
        for scene in SCENES:
            s = get(r, f"table3/{scene}/static/{size}", "mrays_per_cpu_s")
            d = get(r, f"table3/{scene}/dynamic/{size}", "mrays_per_cpu_s")
            row.append(f"{fmt(s)} ({fmt(d)})" if s is not None or d is not None else None)
            row.append(get(r, f"table3/{scene}/static/{size}", "ns_per_pixel"))
        p = PAPER_TABLE3[size]
        row.append(f"{p['office'][0]} ({p['office'][1]})")
        row.append(f"{p['conference'][0]} ({p['conference'][1]})")
        rows.append(row)
    if all(all(c is None for c in row[1:5]) for row in rows):
        return None
    return table(["resolution", "cornell Mrays per CPU-second, static (dynamic)", "cornell ns / pixel",
                  "sponza_lit Mrays per CPU-second, static (dynamic)", "sponza_lit ns / pixel",
                  "paper Office", "paper Conference"], rows)


def fps_table(r):
    rows = []
    for size in ("640x480", "1024x1024"):
        for vpls in (12, 16):
            for aa in (1, 4):
                row = [size, vpls, aa]
                for scene in SCENES:
                    name = f"fps/{scene}/{size}/vpls:{vpls}/aa:{aa}"
                    row += [get(r, name, "fps"), get(r, name, "ms_per_frame"), get(r, name, "cpu_share")]
                row.append(f"{PAPER_FPS[size]} fps on 48 CPUs" if vpls == 12 and aa == 1 else "")
                rows.append(row)
    if all(all(c is None for c in row[3:9]) for row in rows):
        return None
    return table(["size", "VPLs / pixel", "aa", "cornell fps", "cornell ms", "CPU share", "sponza_lit fps", "sponza_lit ms",
                  "CPU share", "paper"], rows)


def threads_table(r):
    rows = []
    for scene in SCENES:
        one = get(r, f"threads/{scene}/threads:1", "ms_per_frame")
        two = get(r, f"threads/{scene}/threads:2", "ms_per_frame")
        if one is None and two is None:
            continue
        rows.append([scene, one, two, one / two if one and two else None,
                     get(r, f"threads/{scene}/threads:1", "cpu_share"), get(r, f"threads/{scene}/threads:2", "cpu_share")])
    if not rows:
        return None
    return table(["scene (640x480, 16 VPLs)", "1 thread ms", "2 threads ms", "speed-up", "CPU share, 1 thread",
                  "CPU share, 2 threads"], rows)


def width_table(r):
    rows = []
    for scene in SCENES:
        ms = {w: get(r, f"width/{scene}/W:{w}", "ms_per_frame") for w in (1, 4, 8, 16)}
        if all(v is None for v in ms.values()):
            continue
        cpu = {w: get(r, f"width/{scene}/W:{w}", "cpu_ms_per_frame") for w in (1, 16)}
        base = ms[1]
        rows.append([scene] + [ms[w] for w in (1, 4, 8, 16)] + [base / ms[16] if base and ms[16] else None,
                                                                  cpu[1] / cpu[16] if cpu[1] and cpu[16] else None])
    if not rows:
        return None
    return table(["scene (640x480, 16 VPLs)", "W=1 ms", "W=4 ms", "W=8 ms", "W=16 ms", "W=16 speed-up over W=1",
                  "same by CPU time"], rows)


def shading_table(r):
    """Packet against single-ray shading (shading_bench): Msamples per CPU second and speed-up over W = 1."""
    widths = [("embree", 1), ("embree", 4), ("embree", 8), ("embree", 16), ("saarcor", 64)]
    rows = []
    for scene in SCENES:
        for name, label in (("shading/{scene}/{backend}/{w}/shadow", "with shadow rays"),
                            ("shading/{scene}/{backend}/{w}/no_shadow", "shading only"),
                            ("surface/{scene}/{backend}/{w}", "surface shader alone (M hit points/s)")):
            rates = {w: get(r, name.format(scene=scene, backend=backend, w=w), "items_per_second") for backend, w in widths}
            if all(v is None for v in rates.values()):
                continue
            base = rates[1]
            cells = [f"{v / 1e6:.1f} ({v / base:.2f}×)" if v and base else fmt(v) for v in rates.values()]
            rows.append([f"{scene}, {label}"] + cells)
    if not rows:
        return None
    return table(["Msamples/s per CPU (speed-up over W=1)", "W=1", "W=4", "W=8", "W=16", "SaarCOR 64"], rows)


def size_rows(r):
    rows = []
    for name in r:
        if not name.startswith("size/") or "skipped" in r[name]:
            continue
        b = r[name]
        rows.append((name, b.get("triangles", 0), b))
    rows.sort(key=lambda t: (t[0].split("/")[1], t[1]))
    return rows


def size_table(r):
    rows = [[name.removeprefix("size/"), b.get("triangles"), b.get("unique_triangles"), b.get("ms_per_frame"),
             b.get("setup_ms"), b.get("cpu_ms_per_frame"), b.get("build_ms"), b.get("bvh_mb"), b.get("build_peak_mb"),
             b.get("scene_mb")]
            for name, _, b in size_rows(r)]
    if not rows:
        return None
    text = table(["scene / cut", "triangles", "unique", "frame ms", "of it set-up ms", "frame CPU ms", "build ms",
                  "BVH MB (resident)", "build peak MB", "igi scene MB"], rows)
    sponza = {name: b for name, _, b in size_rows(r) if name.startswith("size/sponza_lit/n:") and "instances" not in name}
    small, large = sponza.get("size/sponza_lit/n:1"), sponza.get("size/sponza_lit/n:4")
    if small and large:
        text += (f"\n\n262 k → {large['triangles'] / 1e6:.1f} M triangles (Sponza_lit cut 1 → 4): frame time × "
                 f"{large['ms_per_frame'] / small['ms_per_frame']:.2f}, CPU time × "
                 f"{large['cpu_ms_per_frame'] / small['cpu_ms_per_frame']:.2f} (target ≤ 1.5).")
    return text


def load_note(results):
    path = pathlib.Path(results) / "machine.json"
    if not path.exists():
        return None
    m = json.loads(path.read_text())
    return (f"Run of {m.get('date', '?')}: {m.get('seconds', '?')} s in all on {m.get('cores', '?')} cores, "
            f"load average {m.get('load_before', '?')} before and {m.get('load_after', '?')} after "
            f"(`uptime`); {m.get('note', '')}").strip()


def replace_block(text, name, body):
    begin, end = f"<!-- bench:{name} -->", f"<!-- /bench:{name} -->"
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), re.S)
    if not pattern.search(text):
        return text
    return pattern.sub(lambda _: f"{begin}\n{body}\n{end}", text)


def charts(r, results):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = pathlib.Path(results)

    def save(fig, name, *legend_axes):
        for ax in legend_axes:
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / name, dpi=110)
        plt.close(fig)
    # Efficiency: frame vs Embree alone, per scene.
    names = sorted(k for k in r if k.startswith("efficiency/") and "skipped" not in r[k])
    if names:
        fig, ax = plt.subplots(figsize=(6, 3.2))
        labels = [f'{n.split("/")[1]}, {name_field(n, "vpls")} VPLs' for n in names]
        frame = [r[n]["pipeline_ms"] for n in names]
        parts = [("embree_closest_ms", "Embree: primary + secondary"), ("embree_occlusion_ms", "Embree: shadow"),
                 ("embree_single_ms", "Embree: VPL walks")]
        y = range(len(names))
        ax.barh([i + 0.27 for i in y], frame, height=0.27, label="full frame", color="#888")
        left = [0.0] * len(names)
        for key, label in parts:
            values = [r[n][key] for n in names]
            ax.barh(list(y), values, height=0.27, left=left, label=label)
            left = [a + b for a, b in zip(left, values)]
        ax.barh([i - 0.27 for i in y], [r[n].get("ceiling_ms", 0.0) for n in names], height=0.27,
                label="Embree alone on the ceiling scene", color="#444")
        ax.set_yticks(list(y), labels)
        ax.set_xlabel("ms per frame (640x480)")
        ax.set_title("Pipeline against Embree alone on the same rays")
        save(fig, "efficiency.png", ax)
    # Table 3: Mrays/s per thread and ns per pixel against resolution.
    sizes = list(PAPER_TABLE3)
    pixels = [int(s.split("x")[0]) * int(s.split("x")[1]) for s in sizes]
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.4))
    drawn = False
    for scene in SCENES:
        for mode, style in (("static", "-o"), ("dynamic", "--x")):
            mr = [get(r, f"table3/{scene}/{mode}/{s}", "mrays_per_cpu_s") for s in sizes]
            ns = [get(r, f"table3/{scene}/{mode}/{s}", "ns_per_pixel") for s in sizes]
            if any(v is not None for v in mr):
                drawn = True
                a.plot([p for p, v in zip(pixels, mr) if v is not None], [v for v in mr if v is not None], style, label=f"{scene} {mode}")
                b.plot([p for p, v in zip(pixels, ns) if v is not None], [v for v in ns if v is not None], style, label=f"{scene} {mode}")
    if drawn:
        for ax in (a, b):
            ax.set_xscale("log")
            ax.set_xlabel("pixels")
        a.set_ylabel("Mrays per CPU-second")
        b.set_ylabel("ns per pixel (2 threads)")
        a.set_title("Table 3: 16 VPLs, shading, filter")
        b.set_title("Cost per pixel against resolution")
        save(fig, "resolution.png", a)
    else:
        plt.close(fig)
    # Scene size: frame time, build time and memory against triangles.
    rows = size_rows(r)
    if rows:
        fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.4))
        for scene, marker in (("cornell", "o"), ("sponza_lit", "s")):
            pts = [(t, bb) for name, t, bb in rows if name.split("/")[1] == scene and "instances" not in name]
            instanced = [(t, bb) for name, t, bb in rows if name.split("/")[1] == scene and "instances" in name]
            for t, bb in instanced:  # one point apart: the mesh is the 12.8 M one, stored once
                a.plot([t], [bb["ms_per_frame"]], "*", markersize=12, label=f"{scene} 4 instances frame")
                b.plot([t], [bb["build_ms"]], "*", markersize=12, label=f"{scene} 4 instances build ms")
            if not pts:
                continue
            a.plot([t for t, _ in pts], [bb["ms_per_frame"] for _, bb in pts], marker + "-", label=f"{scene} frame")
            a.plot([t for t, _ in pts], [bb["ms_per_frame"] - bb["setup_ms"] for _, bb in pts], marker + ":",
                   label=f"{scene} frame without set-up")
            b.plot([t for t, _ in pts], [bb["build_ms"] for _, bb in pts], marker + "-", label=f"{scene} build ms")
            b.plot([t for t, _ in pts], [bb["bvh_mb"] for _, bb in pts], marker + "--", label=f"{scene} BVH MB")
        for ax in (a, b):
            ax.set_xscale("log")
            ax.set_xlabel("triangles (log)")
        b.set_yscale("log")
        a.set_ylabel("ms per frame (640x480, 16 VPLs)")
        a.set_title("Frame time against scene size")
        b.set_title("Build time and memory")
        save(fig, "scene_size.png", a, b)
    # Frame rates.
    names = [k for k in r if k.startswith("fps/") and "skipped" not in r[k]]
    if names:
        names.sort()
        fig, ax = plt.subplots(figsize=(8, 3.6))
        ax.barh(range(len(names)), [r[n]["fps"] for n in names])
        ax.set_yticks(range(len(names)), [n.removeprefix("fps/") for n in names], fontsize=7)
        ax.axvline(20, color="red", linestyle=":", label="target 20 fps (sponza 640x480, 12 VPLs)")
        ax.set_xlabel("frames per second (2 threads)")
        save(fig, "fps.png", ax)


def main(argv):
    if len(argv) < 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    results, readme = argv[1], pathlib.Path(argv[2])
    r = load(results)
    text = readme.read_text()
    blocks = {
        "machine": load_note(results),
        "efficiency": efficiency_table(r),
        "table1": table1(r),
        "table3": table3(r),
        "fps": fps_table(r),
        "threads": threads_table(r),
        "width": width_table(r),
        "size": size_table(r),
        "shading": shading_table(r),
    }
    for name, body in blocks.items():
        if body is not None:
            text = replace_block(text, name, body)
    readme.write_text(text)
    if "--charts" in argv:
        charts(r, results)
    print(f"report: {len(r)} results from {results}; tables written into {readme}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
