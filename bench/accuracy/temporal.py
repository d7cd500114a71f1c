"""Error of temporal reuse against the frames it has averaged, on a still view of the built-in
Cornell box, the built-in window room, the room with blinds and Sponza_lit (320x240, 16 VPLs per pixel, 3x3, the
discontinuity filter): frame F of igi-render --temporal H --frames F for H = 8 and 32 (and
H = 32 with --vpl-sampler importance), compared with the path-traced references of methods.py
(rendered here if WORK_DIR lacks them); relMSE is the mean over seeds 1-3. The curve of H = 32
keeps falling (its clamp shrinks as the history grows); H = 8 levels off where its exponential
average keeps 1/8 of each new frame. Times are not measured here (each frame costs what a frame
without reuse costs plus the reprojection; see docs/filters.md).

It renders with the Python module built in BUILD_DIR (BUILD_DIR/python): one Renderer per seed
renders the frames in order and is compared after each count of FRAMES, where igi-render would
render every count anew; its frames are igi-render's, bit for bit.

usage: /usr/bin/python3 bench/accuracy/temporal.py BUILD_DIR WORK_DIR OUT_DIR [SCENES_DIR]
writes OUT_DIR/temporal.csv and OUT_DIR/temporal.png.
"""


import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

from methods import SIZE, arguments_and_references, write_csv

# (label, igi-render options as the module's keyword arguments)
CONFIGURATIONS = [
    ("--temporal 8", {"temporal": 8}),
    ("--temporal 32", {"temporal": 32}),
    ("--temporal 32, importance", {"temporal": 32, "vpl_sampler": "importance"}),
]
FRAMES = [1, 2, 4, 8, 16, 32, 64]
SEEDS = [1, 2, 3]  # one frame's error depends on its VPLs' luck (the window room's most of all)
VPLS = 16  # igi's default


def load_scene(igi, scene, scenes_dir):
    """The scene methods.py's scene_arguments names, as the module loads it."""
    if scene == "sponza_lit":
        return igi.load(str(scenes_dir / "sponza" / "Sponza_lit.gltf"))
    return igi.builtin(scene)


def main():
    build, work, out, scenes_dir, references = arguments_and_references("temporal")
    sys.path.insert(0, str(build / "python"))  # the module built beside igi-render
    import igi

    scenes = [scene for scene, _ in references]
    rows = []
    for scene, reference_file in references:
        reference = igi.read_image(str(reference_file))
        loaded = load_scene(igi, scene, scenes_dir)
        for label, options in CONFIGURATIONS:
            errors = {frames: [] for frames in FRAMES}
            for seed in SEEDS:
                renderer = igi.Renderer(loaded, size=SIZE, threads=2, vpls=VPLS, seed=seed, **options)
                for index in range(max(FRAMES)):
                    frame = renderer.render(frame=index)
                    if index + 1 in errors:  # igi-render --frames index+1 writes this frame
                        errors[index + 1].append(igi.relmse(frame.hdr, reference))
            for frames in FRAMES:
                relmse = sum(errors[frames]) / len(errors[frames])
                rows.append({"scene": scene, "configuration": label, "frames": frames, "relmse": relmse,
                             "relmse_per_seed": " ".join(f"{e:.5f}" for e in errors[frames])})
                print(f"{scene:10} {label:26} frame {frames:2}: relMSE {relmse:.4f}", flush=True)
    write_csv(out / "temporal.csv", rows)
    figure, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4.2))
    for axis, scene in zip(axes, scenes):
        for label, _ in CONFIGURATIONS:
            points = [(r["frames"], r["relmse"]) for r in rows if r["scene"] == scene and r["configuration"] == label]
            axis.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=label)
        axis.set_xscale("log", base=2)
        axis.set_yscale("log")
        axis.set_title(f"{scene}, {SIZE}, {VPLS} VPLs, still view, seeds 1-3")
        axis.set_xlabel("frames averaged")
        axis.set_ylabel("relMSE against the path tracer")
        axis.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "temporal.png", dpi=110)
    print(f"temporal: wrote {out / 'temporal.csv'} and {out / 'temporal.png'}")


if __name__ == "__main__":
    main()
