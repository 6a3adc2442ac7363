"""Triangle meshes from OBJ files for the plotting scripts (plot_resolved.py, plot_draped.py)."""
import numpy as np


def load(path):
    """Vertices (#V x 3) and triangles (#F x 3, polygons fanned) of an OBJ file."""
    V, F = [], []
    for line in open(path):
        if line.startswith("v "):
            V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            idx = [int(x.split("/")[0]) - 1 for x in line.split()[1:]]
            F += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    return np.array(V), np.array(F)
