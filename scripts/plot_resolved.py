#!/usr/bin/env python3
"""Resolved garments coloured by displacement (and edge strain), side by side.

usage: plot_resolved.py BODY.obj INPUT.obj OUT.png LABEL=RESOLVED.obj [LABEL=RESOLVED.obj ...]

One row per resolved garment (e.g. objective paper, objective smooth): front, side and back views
of the garment over the body, faces coloured by the largest displacement of their corners
(mm, against INPUT), and a last panel with the edge strain |l / l0 - 1| histogram. Run with
Debian's python3 (matplotlib, numpy)."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from obj_mesh import load  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def edges(F):
    return np.unique(np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), 1), axis=0)


def main():
    body, bf = load(sys.argv[1])
    inp, F = load(sys.argv[2])
    out_png = sys.argv[3]
    runs = [(a.split("=", 1)[0], load(a.split("=", 1)[1])[0]) for a in sys.argv[4:]]
    E = edges(F)
    l0 = np.linalg.norm(inp[E[:, 0]] - inp[E[:, 1]], axis=1)
    lo, hi = inp.min(0) - 0.03, inp.max(0) + 0.03
    near = (body[bf] >= lo).all(2).all(1) & (body[bf] <= hi).all(2).all(1)
    top = max(1e3 * np.linalg.norm(v - inp, axis=1).max() for _, v in runs)
    fig = plt.figure(figsize=(17, 5.2 * len(runs)))
    for r, (label, V) in enumerate(runs):
        disp = 1e3 * np.linalg.norm(V - inp, axis=1)
        strain = np.abs(np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1) / np.maximum(l0, 1e-12) - 1)[l0 > 0]
        colour = plt.cm.inferno(np.clip(disp[F].max(1) / max(top, 1e-9), 0, 1))
        for k, (az, view) in enumerate([(-90, "front"), (0, "side"), (90, "back")]):
            ax = fig.add_subplot(len(runs), 4, 4 * r + k + 1, projection="3d")
            P = lambda X: X[:, [0, 2, 1]]  # noqa: E731  (y up)
            ax.add_collection3d(Poly3DCollection(P(body)[bf[near]], facecolor=(0.75, 0.75, 0.78, 0.2), edgecolor="none"))
            ax.add_collection3d(Poly3DCollection(P(V)[F], facecolors=colour, edgecolor=(0, 0, 0, 0.1), linewidths=0.2))
            c, rad = (lo + hi) / 2, (hi - lo).max() / 2
            ax.set_xlim(c[0] - rad, c[0] + rad)
            ax.set_ylim(c[2] - rad, c[2] + rad)
            ax.set_zlim(c[1] - rad, c[1] + rad)
            ax.set_box_aspect((1, 1, 1), zoom=1.9)
            ax.view_init(0, az)
            ax.axis("off")
            ax.set_title(f"{label}: {view}" + (f"  (max displacement {disp.max():.1f} mm)" if k == 0 else ""), fontsize=9)
        ax = fig.add_subplot(len(runs), 4, 4 * r + 4)
        ax.hist(strain, bins=np.linspace(0, max(1.0, strain.max()), 60), color="tab:blue", log=True)
        ax.axvline(0.3, color="k", linestyle=":", label="0.3")
        ax.set_xlabel("edge strain |l / l0 - 1|")
        ax.set_ylabel("edges")
        ax.set_title(f"{label}: strain max {strain.max():.2f}, p99 {np.percentile(strain, 99):.2f}", fontsize=9)
        ax.legend(fontsize=8)
    sm = plt.cm.ScalarMappable(cmap="inferno", norm=plt.Normalize(0, top))
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="displacement against the input, mm")
    fig.savefig(out_png, dpi=72)


if __name__ == "__main__":
    main()
