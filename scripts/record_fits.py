#!/usr/bin/env python3
"""Waits for tryon_node's results and writes them to a folder: body.obj (the body the node used),
body_report.json, and for each fit garment_<kind>.obj and report_<kind>.json, then renders
result.png (headless, matplotlib). Run it with Debian's /usr/bin/python3 (rospy).

Usage: record_fits.py OUT_DIR [--node /tryon_node] [--kinds resolve,drape] [--timeout 180]
Exits 0 when a fit of every expected kind arrived with success, 1 when one failed, 2 on a
timeout."""
import argparse
import json
import os
import struct
import sys
import threading

import rospy
from pcl_msgs.msg import PolygonMesh
from virtual_tryon.msg import BodyReport, FitReport


def to_dict(msg):
    """A ROS message as plain JSON-able values."""
    if hasattr(msg, "__slots__"):
        return {name: to_dict(getattr(msg, name)) for name in msg.__slots__}
    if isinstance(msg, (list, tuple)):
        return [to_dict(m) for m in msg]
    if isinstance(msg, bytes):
        return len(msg)
    if hasattr(msg, "secs") and hasattr(msg, "nsecs"):
        return msg.secs + 1e-9 * msg.nsecs
    return msg


def mesh_arrays(msg):
    """(vertices, faces) of a pcl_msgs/PolygonMesh with FLOAT32 x, y, z fields."""
    cloud = msg.cloud
    offs = {f.name: f.offset for f in cloud.fields}
    n = cloud.width * cloud.height
    data = cloud.data
    V = []
    for i in range(n):
        base = i * cloud.point_step
        V.append(tuple(struct.unpack_from("<f", data, base + offs[c])[0] for c in "xyz"))
    F = [tuple(p.vertices[:3]) for p in msg.polygons if len(p.vertices) == 3]
    return V, F


def write_obj(path, V, F):
    with open(path, "w") as f:
        f.write("# written by virtual_tryon record_fits.py\n")
        for v in V:
            f.write("v %.6f %.6f %.6f\n" % v)
        for t in F:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def render(path, body, garments):
    """One panel per fit: the body (grey, translucent) and that fit's garment, shaded, seen from
    the front and a little to the side. Body and garment faces are sorted together by depth."""
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    titles = {"resolve": "garment mesh, penetrations resolved", "drape": "pattern sewn and draped"}
    base = {"resolve": (0.15, 0.45, 0.85), "drape": (0.85, 0.35, 0.2)}
    kinds = sorted(garments) or ["(no fit)"]
    fig = plt.figure(figsize=(5 * len(kinds), 8))
    light = np.array([0.4, 0.5, 0.75])
    light /= np.linalg.norm(light)

    def faces(mesh, rgb, alpha):
        # The node's frame has +y up and the body facing +z; matplotlib's 3D axes have z up.
        V = np.asarray(mesh[0])[:, [0, 2, 1]]
        F = np.asarray(mesh[1], dtype=int)
        T = V[F]
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        # The axis swap mirrors the winding: flip the normals back before shading.
        shade = 0.35 + 0.65 * np.abs(-n @ light)
        cols = np.column_stack([np.outer(shade, rgb), np.full(len(F), alpha)])
        return T, cols

    for k, kind in enumerate(kinds):
        ax = fig.add_subplot(1, len(kinds), k + 1, projection="3d")
        T, C = faces(body, (0.75, 0.75, 0.75), 0.35)
        if kind in garments:
            Tg, Cg = faces(garments[kind], base[kind], 1.0)
            T, C = np.concatenate([T, Tg]), np.concatenate([C, Cg])
        ax.add_collection3d(Poly3DCollection(T, facecolors=C, edgecolor="none"))
        ax.set_xlim(-0.5, 0.5)
        ax.set_ylim(-0.5, 0.5)
        ax.set_zlim(0.0, 1.8)
        ax.set_box_aspect((1, 1, 1.8))
        ax.view_init(elev=12, azim=-70)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
        ax.set_zlabel("y (m, up)")
        ax.set_title(titles.get(kind, kind))
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--node", default="/tryon_node")
    ap.add_argument("--kinds", default="resolve,drape")
    ap.add_argument("--timeout", type=float, default=180.0)
    args = ap.parse_args(rospy.myargv()[1:])
    os.makedirs(args.out, exist_ok=True)
    kinds = [k for k in args.kinds.split(",") if k]

    rospy.init_node("record_fits", anonymous=True, disable_signals=True)
    lock = threading.Condition()
    # Garments by header stamp; each report names its garment by the same stamp (the two topics
    # arrive on separate threads, in either order).
    state = {"body": None, "body_report": None, "by_stamp": {}, "reports": {}, "raw_reports": {}}

    def on_body(msg):
        with lock:
            state["body"] = mesh_arrays(msg)
            lock.notify_all()

    def on_body_report(msg):
        with lock:
            state["body_report"] = to_dict(msg)

    def on_garment(msg):
        with lock:
            state["by_stamp"][msg.header.stamp] = msg
            lock.notify_all()

    def on_report(msg):
        with lock:
            state["raw_reports"][msg.kind] = msg
            state["reports"][msg.kind] = to_dict(msg)
            lock.notify_all()

    def garment_of(kind):
        r = state["raw_reports"].get(kind)
        return state["by_stamp"].get(r.header.stamp) if r is not None and r.success else None

    rospy.Subscriber(args.node + "/body", PolygonMesh, on_body)
    rospy.Subscriber(args.node + "/body_report", BodyReport, on_body_report)
    rospy.Subscriber(args.node + "/fitted_garment", PolygonMesh, on_garment, queue_size=10)
    rospy.Subscriber(args.node + "/fit_report", FitReport, on_report, queue_size=10)

    def done():
        return state["body"] is not None and all(
            k in state["reports"] and (garment_of(k) is not None or not state["reports"][k]["success"])
            for k in kinds)

    deadline = rospy.Time.now() + rospy.Duration(args.timeout)
    with lock:
        while not done() and rospy.Time.now() < deadline and not rospy.is_shutdown():
            lock.wait(0.5)
        if not done():
            print("record_fits: timed out after %.0f s; have body: %s, reports: %s" % (
                args.timeout, state["body"] is not None, sorted(state["reports"])), file=sys.stderr)
        write_obj(os.path.join(args.out, "body.obj"), *state["body"]) if state["body"] else None
        with open(os.path.join(args.out, "body_report.json"), "w") as f:
            json.dump(state["body_report"], f, indent=1)
        for kind, report in state["reports"].items():
            with open(os.path.join(args.out, "report_%s.json" % kind), "w") as f:
                json.dump(report, f, indent=1)
        garments = {k: mesh_arrays(garment_of(k)) for k in state["reports"] if garment_of(k) is not None}
        for kind, mesh in garments.items():
            write_obj(os.path.join(args.out, "garment_%s.obj" % kind), *mesh)
        if state["body"]:
            render(os.path.join(args.out, "result.png"), state["body"], garments)
        ok = done() and all(state["reports"][k]["success"] for k in kinds)
        for kind in kinds:
            r = state["reports"].get(kind)
            print("record_fits: %s: %s" % (kind, "missing" if r is None else r["message"]))
    rospy.signal_shutdown("done")
    sys.exit(0 if ok else (2 if not done() else 1))


if __name__ == "__main__":
    main()
