#!/usr/bin/env python3
"""Plots milliseconds per frame against frame from `tryon animate resolve` JSON lines, one file per
garment, with Sun et al. 2016's 30 ms a frame and the 3 ms target.
Usage: /usr/bin/python3 scripts/plot_animation.py OUT.png NAME=FRAMES.jsonl [NAME=FRAMES.jsonl ...]
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def frames(path):
    rows = []
    for line in open(path):
        d = json.loads(line)
        if "frame" in d:
            rows.append(d)
    return rows


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for item in sys.argv[2:]:
        name, path = item.split("=", 1)
        rows = frames(path)
        ax.plot([r["frame"] for r in rows], [r["ms"] for r in rows], label=name, lw=1.2)
    ax.axhline(30, color="grey", ls="--", lw=1)
    ax.text(0.5, 31, "Sun et al. 2016: about 30 ms a frame (their dress, Core2 2.83 GHz)", fontsize=7, color="grey")
    ax.axhline(3, color="red", ls=":", lw=1)
    ax.text(0.5, 3.5, "target: 3 ms a frame", fontsize=7, color="red")
    ax.set_xlabel("frame (30 Hz)")
    ax.set_ylabel("ms per frame (body frame + resolve)")
    ax.set_yscale("log")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title("tryon animate resolve on the MakeHuman walk, every frame on its own", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("plot_animation: wrote " + out)


if __name__ == "__main__":
    main()
