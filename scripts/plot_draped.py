#!/usr/bin/env python3
"""Draped garments on their body, front, side and back, with every boundary edge drawn in red.

usage: plot_draped.py BODY.obj OUT.png LABEL=GARMENT.obj [LABEL=GARMENT.obj ...]

One row per garment: the body in grey, the garment shaded by its faces' normals, and the garment's
boundary edges (edges of one face) in red, so that an opening shows as one red loop and a hole
along a seam as an extra small one. The title gives the loop count. Run with Debian's python3
(matplotlib, numpy)."""
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from obj_mesh import load  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402


def boundary(F):
    count = defaultdict(int)
    for f in F:
        for k in range(3):
            a, b = f[k], f[(k + 1) % 3]
            count[(min(a, b), max(a, b))] += 1
    edges = [e for e, c in count.items() if c == 1]
    parent = {}

    def find(v):
        while parent.setdefault(v, v) != v:
            v = parent[v]
        return v

    for a, b in edges:
        parent[find(a)] = find(b)
    loops = len({find(a) for e in edges for a in e})
    return edges, loops


def shade(V, F, base):
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None] + 1e-12
    light = np.clip(np.abs(n @ np.array([0.3, 0.5, 0.8])), 0.25, 1.0)
    return np.array(base)[None, :] * light[:, None]


def main():
    body, bf = load(sys.argv[1])
    out = sys.argv[2]
    runs = [(a.split("=", 1)[0], load(a.split("=", 1)[1])) for a in sys.argv[3:]]
    views = [("front", 90, -90), ("side", 0, 0), ("back", -90, -90)]
    fig = plt.figure(figsize=(12, 4.2 * len(runs)))
    for r, (label, (V, F)) in enumerate(runs):
        edges, loops = boundary(F)
        lo, hi = V.min(0) - 0.05, V.max(0) + 0.05
        keep = np.all((body[bf].mean(1) > lo - 0.05) & (body[bf].mean(1) < hi + 0.05), axis=1)
        for c, (name, azim, _) in enumerate(views):
            ax = fig.add_subplot(len(runs), 3, 3 * r + c + 1, projection="3d")
            # y up: plot (x, z, y)
            P = lambda X: X[..., [0, 2, 1]]  # noqa: E731
            # matplotlib sorts whole collections, not faces: the body is drawn only behind the
            # garment's middle as seen from the camera, so that it never covers the garment.
            toward = np.array([np.cos(np.radians(azim)), 0.0, np.sin(np.radians(azim))])  # (x, z) of the camera
            depth = body[bf].mean(1) @ np.array([toward[0], 0.0, toward[2]])
            behind = keep & (depth < V.mean(0) @ np.array([toward[0], 0.0, toward[2]]))
            ax.add_collection3d(Poly3DCollection(P(body[bf[behind]]), facecolors=shade(body, bf[behind], [0.8, 0.8, 0.8]),
                                                 linewidths=0))
            ax.add_collection3d(Poly3DCollection(P(V[F]), facecolors=shade(V, F, [0.35, 0.55, 0.9]), linewidths=0))
            ax.add_collection3d(Line3DCollection(P(V[np.array(edges)]) if edges else [], colors="red", linewidths=1.2))
            c0, size = (lo + hi) / 2, (hi - lo).max() / 2
            ax.set_xlim(c0[0] - size, c0[0] + size)
            ax.set_ylim(c0[2] - size, c0[2] + size)
            ax.set_zlim(c0[1] - size, c0[1] + size)
            ax.view_init(elev=5, azim=azim)
            ax.set_axis_off()
            ax.set_title(f"{label}: {name}" + (f" ({loops} boundary loops)" if c == 0 else ""), fontsize=9)
    plt.tight_layout()
    plt.savefig(out, dpi=80)


if __name__ == "__main__":
    main()
