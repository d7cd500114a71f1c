#!/usr/bin/env python3
"""Accuracy sweep: IGI settings and the path tracer against a converged path-traced reference.

usage: sweep.py BUILD_DIR WORK_DIR RESULTS_DIR SCENE...   (SCENE: cornell, sponza_lit)

Called by sweep.sh, which builds igi-render and igi-compare and makes the venv. For each scene:
  1. renders every configuration of `configurations()` with igi-render (HDR PFM and --stats json),
     runs ordered by VPL count first so that load drift hits all methods alike;
  2. renders the reference as chunks of REFERENCE_CHUNK_SPP spp with their own seeds, averages them,
     and measures the reference's own noise from its even against its odd chunks;
  3. compares every run with igi-compare --json and writes RESULTS_DIR/accuracy_<scene>.csv;
  4. draws RESULTS_DIR/accuracy_<scene>_time.png and accuracy_<scene>_vpls.png and writes
     accuracy_<scene>_findings.txt (per time budget: the path tracer's error against the best IGI
     run costing no more).
Renders and reference chunks are cached in WORK_DIR (delete it, or set IGI_ACCURACY_RERUN=1 for
the timed runs, to redo them); charts and CSV are always rewritten.

Environment: IGI_ACCURACY_FRAMES (frames per IGI run, wall-clock timing = their median; default
DEFAULT_FRAMES), IGI_ACCURACY_THREADS (default 2), IGI_ACCURACY_SIZE (default 640x480),
IGI_ACCURACY_REF_SPP_<SCENE> (reference spp, e.g. IGI_ACCURACY_REF_SPP_SPONZA_LIT=1024),
IGI_ACCURACY_RERUN=1, IGI_SCENES_DIR.
"""

import csv
import datetime
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

# Spp of one reference chunk per scene: long enough that start-up is negligible, short enough that
# an interrupted run loses little (Sponza's paths cost about 3.5x Cornell's).
REFERENCE_CHUNK_SPP = {"cornell": 128, "sponza_lit": 64}
# Default reference spp per scene: what one run on the shared 2-core machine (load average 13)
# could afford. The reference's own noise is measured and removed from the charted RMSE (see
# Sweep.reference); more spp (IGI_ACCURACY_REF_SPP_<SCENE>) adds chunks to the cached ones.
DEFAULT_REFERENCE_SPP = {"cornell": 256, "sponza_lit": 256}
# Frames per IGI run (wall-clock time = their median, error = the last frame's). Sponza gets one:
# under a load average of 13 its runs took 10 s of wall clock even at 1 VPL, and the charted
# cost, CPU time per frame, needs no median. IGI_ACCURACY_FRAMES overrides both.
DEFAULT_FRAMES = {"cornell": 3, "sponza_lit": 1}
# Seeds of the reference chunks start here, far from the seeds of the measured runs (0).
REFERENCE_SEED_BASE = 1000
# The renderer's automatic clamp distance is this fraction of the scene's bounding-box diagonal
# (include/igi/render/settings.hpp, resolve_clamp).
AUTOMATIC_CLAMP_FRACTION = 0.02

# Pixels whose reference luminance exceeds this are the directly seen light source (Cornell's
# luminaire: 14.5; its lit walls stay below 0.3, Sponza's sunlit stone below 3, and only 2 of
# Sponza's reference pixels, path-tracer fireflies, pass it). They and their 8 neighbours
# (the luminaire's edge, where IGI's pixel-centre sample and the reference's whole-pixel average
# differ by up to the luminaire's radiance) are left out of the second RMSE.
LUMINAIRE_LUMINANCE = 5.0
# Rec. 709 luminance weights, as igi-compare's SSIM uses.
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)

VPLS = [1, 2, 4, 8, 16, 32, 64, 128, 256]
# Path tracer spp per scene (Sponza's 64 spp would cost another 3 minutes of CPU).
PATH_SPP = {"cornell": [1, 2, 4, 8, 16, 32, 64], "sponza_lit": [1, 2, 4, 8, 16, 32]}
# One-factor clamp sweep: clamp distance as a multiple of the automatic one (0 = no clamp).
CLAMP_FACTORS = [0.0, 0.25, 0.5, 1.0, 2.5]
CLAMP_SWEEP_VPLS = [16, 256]


def scene_arguments(scene, scenes_dir):
    """igi-render's scene arguments for `scene`."""
    if scene == "cornell":
        return ["--builtin", "cornell"]
    return [str(scenes_dir / "sponza" / "Sponza_lit.gltf")]


def quaternion_matrix(q):
    """3x3 rotation of the glTF quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def gltf_diagonal(path):
    """Diagonal of the world bounding box of a glTF file's meshes (from the accessors' min/max)."""
    gltf = json.loads(Path(path).read_text())
    low, high = np.full(3, np.inf), np.full(3, -np.inf)

    def visit(index, parent):
        node = gltf["nodes"][index]
        local = np.eye(4)
        if "matrix" in node:
            local = np.array(node["matrix"], dtype=float).reshape(4, 4).T  # glTF is column-major
        else:
            local[:3, :3] = quaternion_matrix(node.get("rotation", [0, 0, 0, 1])) * np.array(node.get("scale", [1, 1, 1]))
            local[:3, 3] = node.get("translation", [0, 0, 0])
        world = parent @ local
        nonlocal low, high
        for primitive in gltf["meshes"][node["mesh"]]["primitives"] if "mesh" in node else []:
            accessor = gltf["accessors"][primitive["attributes"]["POSITION"]]
            lo, hi = np.array(accessor["min"]), np.array(accessor["max"])
            corners = np.array([[c[0], c[1], c[2], 1.0] for c in np.array(np.meshgrid(*zip(lo, hi))).T.reshape(-1, 3)])
            points = (world @ corners.T).T[:, :3]
            low, high = np.minimum(low, points.min(0)), np.maximum(high, points.max(0))
        for child in node.get("children", []):
            visit(child, world)

    scene = gltf["scenes"][gltf.get("scene", 0)]
    for root in scene["nodes"]:
        visit(root, np.eye(4))
    return float(np.linalg.norm(high - low))


def scene_diagonal(scene, scenes_dir):
    """Bounding-box diagonal that the renderer's automatic clamp is a fraction of."""
    if scene == "cornell":
        # include/igi/scene/cornell.hpp: the box spans 0.556 x 0.5488 x 0.5592 m.
        return math.sqrt(0.556 ** 2 + 0.5488 ** 2 + 0.5592 ** 2)
    return gltf_diagonal(scenes_dir / "sponza" / "Sponza_lit.gltf")


def configurations(scene):
    """Every measured run: (run id, method label, sweep name, settings dict)."""
    runs = []
    default = {"integrator": "igi", "interleave": 3, "filter": "discontinuity", "aa": 1, "clamp_factor": None}
    for vpls in VPLS:
        # Main sweep: each interleaving with each filter (a 1 x 1 pattern has nothing to filter).
        for interleave in (1, 3, 5):
            for filter_name in (("none",) if interleave == 1 else ("none", "box", "discontinuity")):
                settings = dict(default, vpls=vpls, interleave=interleave, filter=filter_name)
                runs.append((f"igi_s{interleave}_{filter_name}_v{vpls}", f"IGI {interleave}x{interleave} {filter_name}",
                             "main", settings))
        # Anti-aliasing 4 beside the default (each sub-sample needs a VPL of its own: vpls >= aa).
        if vpls >= 4:
            runs.append((f"igi_aa4_v{vpls}", "IGI 3x3 discontinuity aa4", "aa", dict(default, vpls=vpls, aa=4)))
        # No clamp beside the default, over the whole VPL range: shows whether the floor is clamp bias.
        runs.append((f"igi_noclamp_v{vpls}", "IGI 3x3 discontinuity no clamp", "clamp_off",
                     dict(default, vpls=vpls, clamp_factor=0.0)))
        if vpls in CLAMP_SWEEP_VPLS:
            for factor in CLAMP_FACTORS:
                if factor in (0.0, 1.0):
                    continue  # the clamp_off curve and the main sweep hold these
                runs.append((f"igi_clamp{factor:g}_v{vpls}", f"IGI clamp x{factor:g}", "clamp",
                             dict(default, vpls=vpls, clamp_factor=factor)))
    for spp in PATH_SPP[scene]:
        runs.append((f"path_spp{spp}", "path tracer", "path", {"integrator": "path", "spp": spp}))
    return runs


def run_json(command):
    """Runs a program that prints one JSON object on stdout; exits with its message if it fails."""
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"sweep: {' '.join(command)} failed: {result.stderr.strip()}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def read_pfm(path):
    """A PFM image as a float32 array of rows in stored order."""
    data = Path(path).read_bytes()
    parts, offset = [], 0
    while len(parts) < 3:  # magic, size, scale: three whitespace-ended tokens lines
        end = data.index(b"\n", offset)
        parts.append(data[offset:end])
        offset = end + 1
    width, height = map(int, parts[1].split())
    scale = float(parts[2])
    dtype = "<f4" if scale < 0 else ">f4"
    pixels = np.frombuffer(data, dtype=dtype, count=width * height * 3, offset=offset).reshape(height, width, 3)
    return pixels.astype(np.float32)


def write_pfm(path, pixels):
    """Writes `pixels` (rows in the order read_pfm returns them) as a little-endian PFM."""
    height, width, _ = pixels.shape
    with open(path, "wb") as out:
        out.write(b"PF\n" + f"{width} {height}\n".encode() + b"-1.0\n")
        out.write(pixels.astype("<f4").tobytes())


def outside_luminaire(reference):
    """Mask of the pixels neither on nor next to a pixel brighter than LUMINAIRE_LUMINANCE."""
    bright = np.pad((reference @ LUMINANCE_WEIGHTS) > LUMINAIRE_LUMINANCE, 1)  # a False border
    height, width = reference.shape[:2]
    near = np.zeros((height, width), dtype=bool)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            near |= bright[dy:dy + height, dx:dx + width]
    return ~near


def masked_rmse(test, reference, mask):
    """RMSE over the pixels of `mask` and the three channels."""
    return float(np.sqrt(np.mean((test[mask] - reference[mask]) ** 2)))


class Sweep:
    """One scene's runs, reference, comparisons and charts."""

    def __init__(self, scene, build, work, results):
        self.scene = scene
        self.render = build / "examples" / "render" / "igi-render"
        self.compare = build / "examples" / "compare" / "igi-compare"
        self.work = work / scene
        self.results = results
        self.scenes_dir = Path(os.environ.get("IGI_SCENES_DIR", Path(__file__).resolve().parents[2] / ".." / "shared" / "scenes"))
        self.frames = int(os.environ.get("IGI_ACCURACY_FRAMES", DEFAULT_FRAMES[scene]))
        self.threads = os.environ.get("IGI_ACCURACY_THREADS", "2")
        self.size = os.environ.get("IGI_ACCURACY_SIZE", "640x480")
        self.reference_spp = int(os.environ.get(f"IGI_ACCURACY_REF_SPP_{scene.upper()}", DEFAULT_REFERENCE_SPP[scene]))
        self.rerun = os.environ.get("IGI_ACCURACY_RERUN") == "1"
        self.diagonal = scene_diagonal(scene, self.scenes_dir)
        (self.work / "runs").mkdir(parents=True, exist_ok=True)
        (self.work / "reference").mkdir(parents=True, exist_ok=True)

    def common_arguments(self):
        return scene_arguments(self.scene, self.scenes_dir) + ["--size", self.size, "--threads", self.threads,
                                                               "--stats", "json"]

    def render_run(self, run_id, settings):
        """Renders one configuration (cached); returns its statistics with the load average."""
        image, stats_file = self.work / "runs" / f"{run_id}.pfm", self.work / "runs" / f"{run_id}.json"
        if image.exists() and stats_file.exists() and not self.rerun:
            stats = json.loads(stats_file.read_text())
            if settings["integrator"] == "path" or stats["frames"] == self.frames:
                return stats
        command = [str(self.render)] + self.common_arguments() + ["-o", str(image)]
        if settings["integrator"] == "path":
            command += ["--integrator", "path", "--spp", str(settings["spp"]), "--frames", "1"]
        else:
            # --temporal 0: the sweep measures single frames (igi-render averages its --frames by default).
            command += ["--vpls", str(settings["vpls"]), "--interleave", str(settings["interleave"]),
                        "--filter", settings["filter"], "--aa", str(settings["aa"]), "--frames", str(self.frames),
                        "--temporal", "0"]
            if settings["clamp_factor"] is not None:
                clamp = settings["clamp_factor"] * AUTOMATIC_CLAMP_FRACTION * self.diagonal
                command += ["--clamp", f"{clamp:.6g}"]
        load_before, cpu_before = os.getloadavg()[0], os.times()
        stats = run_json(command)
        cpu_after = os.times()
        stats["load_before"], stats["load_after"] = load_before, os.getloadavg()[0]
        # CPU seconds of the whole process (scene loading included): less disturbed by the load.
        stats["process_cpu_s"] = (cpu_after.children_user + cpu_after.children_system -
                                  cpu_before.children_user - cpu_before.children_system)
        stats["process_wall_s"] = cpu_after.elapsed - cpu_before.elapsed
        stats_file.write_text(json.dumps(stats))
        return stats

    def setup_cpu_seconds(self):
        """CPU seconds igi-render spends outside its frames (loading, BVH): the median of three
        runs of a 16 x 16 single-VPL frame, whose own cost is negligible."""
        seconds = []
        for i in range(3):
            path = self.work / "runs" / f"setup_{i}.json"
            if path.exists() and not self.rerun:
                stats = json.loads(path.read_text())
            else:
                before = os.times()
                stats = run_json([str(self.render)] + scene_arguments(self.scene, self.scenes_dir) +
                                 ["--size", "16x16", "--vpls", "1", "--threads", self.threads, "--stats", "json",
                                  "-o", str(self.work / "runs" / "setup.pfm")])
                after = os.times()
                stats["process_cpu_s"] = (after.children_user + after.children_system -
                                          before.children_user - before.children_system)
                path.write_text(json.dumps(stats))
            seconds.append(stats["process_cpu_s"])
        return sorted(seconds)[1]

    def reference(self):
        """Renders the missing reference chunks; returns (reference path, its noise RMSE, spp)."""
        chunk_spp = REFERENCE_CHUNK_SPP[self.scene]
        chunks = max(2, 2 * round(self.reference_spp / (2 * chunk_spp)))  # an even count: two halves
        images = []
        for i in range(chunks):
            seed = REFERENCE_SEED_BASE + i
            path = self.work / "reference" / f"chunk_seed{seed}_spp{chunk_spp}.pfm"
            if not path.exists():
                started = time.time()
                partial = path.with_suffix(".tmp.pfm")
                run_json([str(self.render)] + self.common_arguments() +
                         ["--integrator", "path", "--spp", str(chunk_spp), "--seed", str(seed), "-o", str(partial)])
                partial.rename(path)
                print(f"  reference chunk {i + 1}/{chunks}: {time.time() - started:.0f} s", flush=True)
            images.append(read_pfm(path))
        even, odd = np.mean(images[0::2], axis=0), np.mean(images[1::2], axis=0)
        reference, half_even, half_odd = (self.work / f"reference_{chunks * chunk_spp}spp.pfm",
                                          self.work / "reference_half_even.pfm", self.work / "reference_half_odd.pfm")
        write_pfm(reference, 0.5 * (even + odd))
        write_pfm(half_even, even)
        write_pfm(half_odd, odd)
        halves = run_json([str(self.compare), "--json", str(half_even), str(half_odd)])
        self.reference_pixels = 0.5 * (even + odd)
        self.mask = outside_luminaire(self.reference_pixels)
        # The halves are independent estimates with twice the reference's variance each, so their
        # difference has four times it: the reference's own RMSE against the truth is half theirs.
        self.reference_noise_outside = 0.5 * masked_rmse(even, odd, self.mask)
        return reference, 0.5 * halves["rmse"], chunks * chunk_spp, halves

    def run(self):
        runs = configurations(self.scene)
        started = time.time()
        print(f"{self.scene}: {len(runs)} runs, load average {os.getloadavg()[0]:.2f}", flush=True)
        rows = []
        for n, (run_id, method, sweep, settings) in enumerate(runs, 1):
            stats = self.render_run(run_id, settings)
            rows.append((run_id, method, sweep, settings, stats))
            print(f"  [{n}/{len(runs)}] {run_id}: {stats['ms_per_frame']:.1f} ms (load {stats['load_before']:.1f})", flush=True)
        sweep_seconds = time.time() - started
        setup = self.setup_cpu_seconds()
        reference, reference_noise, reference_spp, halves = self.reference()
        print(f"  reference {reference_spp} spp: its noise RMSE {reference_noise:.5f} (halves: RMSE {halves['rmse']:.5f}, "
              f"relMSE {halves['relmse']:.5f}, SSIM {halves['ssim']:.4f})", flush=True)
        table = []
        for run_id, method, sweep, settings, stats in rows:
            image = str(self.work / "runs" / f"{run_id}.pfm")
            metrics = run_json([str(self.compare), "--json", str(reference), image])
            # The same without the brightest 0.1% of reference pixels (the visible luminaire).
            without_brightest = run_json([str(self.compare), "--json", "--ignore-brightest", str(reference), image])
            outside = masked_rmse(read_pfm(image), self.reference_pixels, self.mask)
            clamp_factor = settings.get("clamp_factor")
            table.append({
                "scene": self.scene, "run": run_id, "method": method, "sweep": sweep,
                "integrator": settings["integrator"], "vpls_per_pixel": settings.get("vpls", ""),
                "interleave": settings.get("interleave", ""), "filter": settings.get("filter", ""),
                "aa": settings.get("aa", ""),
                "clamp_factor": "" if settings["integrator"] == "path" else (1.0 if clamp_factor is None else clamp_factor),
                "clamp_distance": "" if settings["integrator"] == "path" else
                AUTOMATIC_CLAMP_FRACTION * self.diagonal * (1.0 if clamp_factor is None else clamp_factor),
                "spp": settings.get("spp", ""), "vpls_per_frame": stats.get("vpls_per_frame", ""),
                # What a pixel connects to: the mean set size. The sampler starts whole walks, at
                # least one per set, so small requests (M = 1, 2, 4 on Cornell) give the same sets.
                "vpls_per_set": stats["vpls_per_frame"] / settings["interleave"] ** 2 if "vpls" in settings else "",
                "frames": stats["frames"], "ms_per_frame": stats["ms_per_frame"], "vpl_ms": stats.get("vpl_ms", ""),
                "rays_primary": stats["rays_primary"], "rays_shadow": stats["rays_shadow"],
                "rays_secondary": stats["rays_secondary"],
                "rmse": metrics["rmse"], "relmse": metrics["relmse"],
                "relmse_ignore_brightest": without_brightest["relmse"], "ssim": metrics["ssim"],
                # MSE against a noisy reference = true MSE + the reference's variance.
                "rmse_minus_reference_noise": math.sqrt(max(metrics["rmse"] ** 2 - reference_noise ** 2, 0.0)),
                "rmse_outside_luminaire": outside,
                "rmse_outside_luminaire_minus_reference_noise":
                    math.sqrt(max(outside ** 2 - self.reference_noise_outside ** 2, 0.0)),
                "reference_spp": reference_spp, "reference_noise_rmse": reference_noise,
                "reference_noise_rmse_outside_luminaire": self.reference_noise_outside,
                "pixels_outside_luminaire": int(self.mask.sum()),
                "load_before": stats["load_before"], "load_after": stats["load_after"],
                "process_cpu_s": stats["process_cpu_s"], "process_wall_s": stats["process_wall_s"],
                "setup_cpu_s": setup,
                # CPU time of one frame (all threads): the process's less its set-up, per frame.
                "cpu_ms_per_frame": max(stats["process_cpu_s"] - setup, 0.0) * 1e3 / stats["frames"],
                "threads": stats["threads"], "width": stats["width"], "height": stats["height"],
            })
        out = self.results / f"accuracy_{self.scene}.csv"
        with open(out, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(table[0]))
            writer.writeheader()
            writer.writerows(table)
        print(f"  wrote {out} ({len(table)} rows; timed runs {sweep_seconds / 60:.1f} min, "
              f"{datetime.datetime.now():%Y-%m-%d %H:%M})", flush=True)
        import charts  # beside this file; imported late so that a missing matplotlib fails after the renders
        with open(out, newline="") as f:
            written = list(csv.DictReader(f))
        charts.draw(written, self.results, self.scene)
        text = "\n".join(charts.findings(written, self.scene, key) for key in ("cpu_ms_per_frame", "ms_per_frame"))
        (self.results / f"accuracy_{self.scene}_findings.txt").write_text(text + "\n")


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    build, work, results = (Path(a).resolve() for a in sys.argv[1:4])
    results.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    for scene in sys.argv[4:]:
        if scene not in DEFAULT_REFERENCE_SPP:
            sys.exit(f"sweep: unknown scene '{scene}' (cornell, sponza_lit)")
        Sweep(scene, build, work, results).run()


if __name__ == "__main__":
    main()
