"""Draws igi-walkthrough's JSON: per walk, each method's relMSE and image mean (over the
reference's) frame by frame, and a findings table of the numbers the stability targets name
(the image mean's coefficient of variation over the walk, the median and worst relMSE, the
median flicker: how far each pixel's change from the frame before departs from the reference's,
with the part the reference's own noise explains in brackets; the median frame time).

usage: python3 bench/walkthrough/charts.py WALKTHROUGH_JSON OUT_DIR
writes OUT_DIR/walkthrough.png and OUT_DIR/walkthrough_findings.txt.
"""

import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt


def main():
    data = json.loads(Path(sys.argv[1]).read_text())
    out = Path(sys.argv[2])
    walks = data["walks"]
    lines = [f"walkthroughs: {data['size']}, {data['frames']} frames at {data['fps']} fps, references "
             f"{data['reference_spp']} spp (pixel centres, textures read over the camera rays' footprint as IGI's), {data['threads']} threads",
             f"{'walk':16} {'method':18} {'mean CV':>8} {'relMSE med':>10} {'relMSE worst':>12} "
             f"{'flicker med':>11} {'(floor)':>8} {'ms med':>8}"]
    figure, axes = plt.subplots(2, len(walks), figsize=(4.2 * len(walks), 7), squeeze=False)
    for column, walk in enumerate(walks):
        for method in walk["methods"]:
            frames = method["frames"]
            axes[0][column].plot([f["frame"] for f in frames], [f["relmse"] for f in frames], label=method["method"])
            axes[1][column].plot([f["frame"] for f in frames], [f["mean_ratio"] for f in frames], label=method["method"])
            lines.append(f"{walk['walk']:16} {method['method']:18} {100 * method['mean_ratio_cv']:7.1f}% "
                         f"{method['relmse_median']:10.4f} {method['relmse_worst']:12.4f} "
                         f"{100 * method['flicker_median']:10.1f}% {100 * method['flicker_floor_median']:7.1f}% {method['ms_median']:8.1f}")
        axes[0][column].set_title(walk["walk"])
        axes[0][column].set_yscale("log")
        axes[0][column].set_ylabel("relMSE against the path tracer")
        axes[1][column].set_ylabel("image mean / reference's")
        axes[1][column].set_xlabel("frame")
        for row in (0, 1):
            axes[row][column].grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "walkthrough.png", dpi=100)
    (out / "walkthrough_findings.txt").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
