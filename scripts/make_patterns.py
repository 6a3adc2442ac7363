#!/usr/bin/env python3
"""Writes the shipped garment patterns (config/patterns/<body>/*.yaml) from body measurements.

Each body is described by a few landmarks (metres, +y up, the body faces +z); every garment is
cut from them: a skirt (2 panels), trousers (4), a sleeveless shirt (2), a T-shirt with sleeves
(2 + 2) and a strapless dress (2). Panels start wrapped round the body's vertical axis (or a
leg's or an arm's axis) a few centimetres out, so that the seams pull them in onto the body.
Widths come from measured torso girths (the convex-hull perimeter of the body's cross-section
every 2 cm, from the hips to the armpits: `--measure BODY.obj Y0 Y1` prints such a table), so a
side seam or an outseam never has to stretch the cloth round a body wider than its pattern.
Run: /usr/bin/python3 scripts/make_patterns.py  (no third-party modules).
"""
import math
import os
import sys

# Measured on ../shared/data/body_hm08.obj (cross-sections every 5 cm; see the closing note).
HM08 = dict(
    name="hm08", axis_x=0.0, axis_z=0.04, waist_ease=1.15,
    neck_y=0.60, shoulder_y=0.52, armpit_y=0.43, chest_y=0.35, waist_y=0.22, hip_y=0.03,
    crotch_y=-0.09, knee_y=-0.42, ankle_y=-0.72,
    chest_rx=0.135, chest_rz=0.098, waist_rx=0.124, waist_rz=0.090, hip_rx=0.176, hip_rz=0.114,
    shoulder_x=0.17, neck_rx=0.06,
    leg_x=0.135, leg_z=0.03, thigh_r=0.085, ankle_r=0.05,
    hip_joint=(0.09, -0.02, 0.03), ankle=(0.19, -0.72, 0.01),
    shoulder_joint=(0.19, 0.45, 0.04), elbow=(0.36, 0.29, 0.08), arm_r=0.045,
    rise=0.662,  # measure_rise at x = 0 below the waist
    shoulder_top_y=0.565,  # the top of the shoulder between neck and arm (shoulder_y: the joints)
    # Torso girths (y, convex-hull perimeter of the cross-section, its front part; measure_girths),
    # hips to armpits.
    girth=[(-0.04, 0.978, 0.448), (-0.02, 0.973, 0.443), (0.0, 0.968, 0.439), (0.02, 0.963, 0.437),
           (0.04, 0.959, 0.436), (0.06, 0.955, 0.434), (0.08, 0.943, 0.431), (0.1, 0.925, 0.424),
           (0.12, 0.902, 0.415), (0.14, 0.874, 0.404), (0.16, 0.836, 0.39), (0.18, 0.793, 0.376),
           (0.2, 0.745, 0.362), (0.22, 0.704, 0.349), (0.24, 0.681, 0.34), (0.26, 0.67, 0.333),
           (0.28, 0.671, 0.33), (0.3, 0.681, 0.333), (0.32, 0.699, 0.344), (0.34, 0.718, 0.37),
           (0.36, 0.747, 0.414), (0.38, 0.789, 0.447), (0.4, 0.807, 0.462), (0.42, 0.824, 0.488)],
)

# The project's procedural body (include/virtual_tryon/core/scenes/procedural_body.h, default
# parameters: 1.70 m, feet at y = 0), from proceduralBodyLandmarks(); test_procedural_body checks
# that these numbers still match the body.
PROCEDURAL = dict(
    name="procedural", axis_x=0.0, axis_z=0.0, waist_ease=1.10,
    neck_y=1.47, shoulder_y=1.43, armpit_y=1.31, chest_y=1.24, waist_y=1.05, hip_y=0.88,
    crotch_y=0.755, knee_y=0.48, ankle_y=0.08,
    chest_rx=0.166, chest_rz=0.110, waist_rx=0.138, waist_rz=0.094, hip_rx=0.182, hip_rz=0.113,
    shoulder_x=0.15, neck_rx=0.056,
    leg_x=0.105, leg_z=0.0, thigh_r=0.088, ankle_r=0.045,
    hip_joint=(0.094, 0.875, -0.004), ankle=(0.128, 0.08, -0.022),
    shoulder_joint=(0.178, 1.385, -0.012), elbow=(0.38, 1.183, -0.012), arm_r=0.05,
    rise=0.734,  # measure_rise at x = 0 below the waist
    shoulder_top_y=1.449,  # the top of the shoulder between neck and arm
    # Torso girths, as for HM08, on the body written as OBJ.
    girth=[(0.76, 0.885, 0.439), (0.78, 0.893, 0.442), (0.8, 0.903, 0.444), (0.82, 0.919, 0.447),
           (0.84, 0.943, 0.451), (0.86, 0.962, 0.456), (0.88, 0.963, 0.458), (0.9, 0.947, 0.45),
           (0.92, 0.917, 0.464), (0.94, 0.881, 0.446), (0.96, 0.851, 0.433), (0.98, 0.829, 0.426),
           (1.0, 0.8, 0.387), (1.02, 0.771, 0.377), (1.04, 0.749, 0.371), (1.06, 0.744, 0.373),
           (1.08, 0.75, 0.38), (1.1, 0.764, 0.39), (1.12, 0.781, 0.401), (1.14, 0.798, 0.413),
           (1.16, 0.815, 0.401), (1.18, 0.833, 0.406), (1.2, 0.854, 0.418), (1.22, 0.871, 0.428),
           (1.24, 0.884, 0.435), (1.26, 0.889, 0.436), (1.28, 0.891, 0.434)],
)


def read_obj(path):
    V, F = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                V.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "f":
                idx = [int(x.split("/")[0]) for x in t[1:]]
                idx = [i - 1 if i > 0 else len(V) + i for i in idx]
                F.extend((idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1))
    return V, F


def hull_perimeter(pts):
    """Perimeter of the convex hull of 2D (x, z) points (monotone chain) and the length of its
    +z chain between the extreme x points (the front half; the back is the rest)."""
    pts = sorted(set(pts))
    if len(pts) < 3:
        return 0.0, 0.0

    def turn(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and turn(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and turn(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    def length(chain):
        return sum(math.hypot(chain[i][0] - chain[i - 1][0], chain[i][1] - chain[i - 1][1]) for i in range(1, len(chain)))
    return length(lower) + length(upper), length(upper)


def measure_girths(path, ys, axis_x=0.0, gap=0.025):
    """Torso girths: at each height y the body's cross-section is cut, its points split where
    their x coordinates leave a gap wider than `gap` (arms, separate legs), and the convex hull
    perimeter (what a cloth wrapped round it spans) of the piece containing axis_x is taken, with
    its front part (+z, between the extreme x points). Returns [(y, girth, front), ...]."""
    V, F = read_obj(path)
    out = []
    for y in ys:
        pts = []
        for tri in F:
            P = [V[i] for i in tri]
            for i in range(3):
                a, b = P[i], P[(i + 1) % 3]
                if (a[1] < y) != (b[1] < y):
                    t = (y - a[1]) / (b[1] - a[1])
                    pts.append((a[0] + t * (b[0] - a[0]), a[2] + t * (b[2] - a[2])))
        pts.sort()
        lo = hi = None
        start = 0
        for k in range(1, len(pts) + 1):
            if k == len(pts) or pts[k][0] - pts[k - 1][0] > gap:
                if pts[start][0] <= axis_x <= pts[k - 1][0]:
                    lo, hi = start, k
                start = k
        if lo is not None:
            total, front = hull_perimeter(pts[lo:hi])
            out.append((round(y, 4), round(total, 3), round(front, 3)))
    return out


def measure_rise(path, x, y_top):
    """The crotch loop: the body cut by the plane at x (sagittal), below y_top (the waist), as a
    cloth spans it: the convex hull perimeter of the cut clipped to y <= y_top, less its top edge
    (the chord from the front to the back at y_top). A front and a back rise of the trousers
    together must be at least this long, or the crotch seams cannot meet under the body."""
    V, F = read_obj(path)
    pts = []
    for tri in F:
        P = [V[i] for i in tri]
        cut = []
        for i in range(3):
            a, b = P[i], P[(i + 1) % 3]
            if (a[0] < x) != (b[0] < x):
                t = (x - a[0]) / (b[0] - a[0])
                cut.append((a[2] + t * (b[2] - a[2]), a[1] + t * (b[1] - a[1])))
        if len(cut) != 2:
            continue
        (za, ya), (zb, yb) = cut
        if ya > y_top and yb > y_top:
            continue
        if (ya > y_top) != (yb > y_top):
            t = (y_top - ya) / (yb - ya)
            top = (za + t * (zb - za), y_top)
            cut = [top, (za, ya) if ya <= y_top else (zb, yb)]
        pts.extend(cut)
    if len(pts) < 3:
        return 0.0
    total, _ = hull_perimeter(pts)
    at_top = [z for z, y in pts if y >= y_top - 1e-9]
    return round(total - (max(at_top) - min(at_top)), 3)


def girth(L, y, part="all"):
    """The body's torso girth at height y (linear between the measured heights, clamped); part
    "front" or "back": the half in front of or behind the extreme x points; "larger": the
    larger of the two."""
    def value(row):
        return {"all": row[1], "front": row[2], "back": row[1] - row[2], "larger": max(row[2], row[1] - row[2])}[part]
    g = L["girth"]
    if y <= g[0][0]:
        return value(g[0])
    for a, b in zip(g, g[1:]):
        if y <= b[0]:
            return value(a) + (value(b) - value(a)) * (y - a[0]) / (b[0] - a[0])
    return value(g[-1])


def max_girth(L, ya, yb, part="all"):
    ys = [ya, yb] + [row[0] for row in L["girth"] if ya < row[0] < yb]
    return max(girth(L, y, part) for y in ys)


def fit_side(L, y0, lo, hi, need):
    """Points (u, v) strictly between the side-line ends lo = (u, v) and hi (v measured from y0)
    so that the piecewise-linear side line keeps u >= need(y) at every measured height between
    them: the worst shortfall is lifted onto the line first, until none is left."""
    line = [lo, hi]
    for _ in range(32):
        worst, at = 1e-4, None
        for row in L["girth"]:
            y = row[0]
            v = y - y0
            if not (lo[1] < v < hi[1]):
                continue
            for a, b in zip(line, line[1:]):
                if a[1] <= v <= b[1]:
                    u = a[0] + (b[0] - a[0]) * (v - a[1]) / (b[1] - a[1])
                    if need(y) - u > worst:
                        worst, at = need(y) - u, (need(y), v)
        if at is None:
            break
        line.append(at)
        line.sort(key=lambda p: p[1])
    return line[1:-1]


def perimeter(a, b):
    """Ellipse perimeter (Ramanujan)."""
    h = ((a - b) / (a + b)) ** 2
    return math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))


def fmt(x):
    return ("%.4f" % x).rstrip("0").rstrip(".") if abs(x) > 1e-12 else "0"


def outline(points):
    return "[" + ", ".join("[%s, %s]" % (fmt(u), fmt(v)) for u, v in points) + "]"


def panel(name, pts, translation, rpy=(0, 0, 0), wrap=0.0, comment=None, quaternion=None):
    lines = []
    if comment:
        lines.append("  # " + comment)
    lines.append("  - name: %s" % name)
    lines.append("    outline: %s" % outline(pts))
    lines.append("    placement:")
    lines.append("      translation: [%s]" % ", ".join(fmt(t) for t in translation))
    if quaternion is not None:
        lines.append("      rotation_quaternion: [%s]" % ", ".join(repr(float(q)) for q in quaternion))
    elif any(abs(r) > 0 for r in rpy):
        lines.append("      rotation_rpy: [%s]" % ", ".join(repr(float(r)) for r in rpy))
    if wrap > 0:
        lines.append("      wrap_radius: %s" % fmt(wrap))
    return "\n".join(lines)


def seam(a, af, at, b, bf, bt, comment=None, stage=0):
    s = "  - a: {panel: %s, from: %d, to: %d}\n    b: {panel: %s, from: %d, to: %d}" % (a, af, at, b, bf, bt)
    if stage:
        s += "\n    stage: %d" % stage
    return ("  # " + comment + "\n" + s) if comment else s


def document(name, header, panels, seams):
    return "\n".join(["# " + l for l in header.splitlines()] + ["name: %s" % name, "panels:"] + panels +
                     ["seams:"] + seams) + "\n"


def mirror(pts):
    """Mirror an outline in u and keep it counter-clockwise: (u, v) -> (-u, v), order reversed."""
    return [(-u, v) for u, v in reversed(pts)]


HALF_TURN = (0, 0, math.pi)  # rpy: turned about +y (R = Rz Ry Rx, pitch is about y)
BACK = (0, math.pi, 0)


def wrap_radius(R, half_width):
    """At least R, and wide enough that a panel of this half-width covers at most 0.95 of a half
    turn: front and back panels then start apart at the sides instead of overlapping, where a
    side seam would have to pull its edges through each other (and round an arm at the armpit)."""
    return max(R, half_width / (0.95 * math.pi / 2))


def side_line(L, y0, lo, hi, ease, inner=lambda v: 0.0):
    """The right side of a panel from lo = (u, v) up to hi, with points added where the body is
    wider than the straight line: u + inner(v) >= ease * girth / 4 at every measured height (a
    front or a back panel spans half the girth; inner(v) is what the panel's other side adds)."""
    return fit_side(L, y0, lo, hi, lambda y: ease * girth(L, y) / 4 - inner(y - y0))


def skirt(L):
    y0 = L["knee_y"] + 0.06
    top = L["waist_y"] - y0
    wt = 0.5 * girth(L, L["waist_y"]) * 1.12
    wb = 0.5 * max_girth(L, L["crotch_y"], L["waist_y"]) * 1.35
    R = wrap_radius(max(L["hip_rx"], L["hip_rz"]) + 0.05, wb / 2)
    side = side_line(L, y0, (wb / 2, 0), (wt / 2, top), 1.06)
    right = [(wb / 2, 0)] + side + [(wt / 2, top)]
    pts = [(-wb / 2, 0)] + right + [(-u, v) for u, v in reversed(right[1:])]
    n, w = len(pts), len(right)  # w: index of the waist's right end
    m = lambda i: (n + 1 - i) % n  # noqa: E731  the same point on the left side (u -> -u)
    # Each side seam in two stretches (hem to the widest point, then to the waist), so that no
    # stretch goes half-way round the outline or more.
    h = 1 + max(range(len(right)), key=lambda i: right[i][0] if 0 < i < len(right) - 1 else -1)
    h = h if 1 < h < w else (1 + w) // 2
    t = (L["axis_x"], y0, L["axis_z"])
    return document("skirt", "A-line skirt, knee length: front and back panels wrapped round the body's axis,\n"
                    "sewn at both sides. Generated by scripts/make_patterns.py for %s." % L["name"],
                    [panel("front", pts, t, wrap=R), panel("back", pts, t, BACK, wrap=R)],
                    [seam("front", 1, h, "back", m(1), m(h), "right side (+x), hem to hips"),
                     seam("front", h, w, "back", m(h), m(w), "right side (+x), hips to waist"),
                     seam("front", m(1), m(h), "back", 1, h, "left side (-x), hem to hips"),
                     seam("front", m(h), m(w), "back", h, w, "left side (-x), hips to waist")])


def shirt_outline(L, y0, flare=1.0, sleeveless=True):
    """Front/back outline from the hem (v = 0) to the shoulders and the indices of its points:
    hem_l, hem_r, armpit_r, sh_out_r, sh_in_r, neck, sh_in_l, sh_out_l, armpit_l (the side lines
    from the hem to the armpits may carry points in between, where the body is wider than the
    straight line). Widths from the measured girths: the armpit 12% over the body's girth at its
    height, the hem 12% over the widest hip (times the flare)."""
    # Side seams end below the armpit: 2 cm where a sleeve is set in; 4 cm without sleeves, where
    # the straps, sewn at the same time, lift the panels (no gravity while sewing) and pulled
    # the seam's ends up into the armpit crease with the arm between them (the procedural dress
    # at 4 cm spacing kept its side seams 8 cm open there).
    h_arm = L["armpit_y"] - y0 - (0.04 if sleeveless else 0.02)
    w_arm = 0.5 * girth(L, y0 + h_arm) * 1.12
    w_hem = 0.5 * max_girth(L, y0, y0 + 0.1) * 1.12 * flare
    h_sh = L["shoulder_y"] - y0 + 0.10  # straps start well above the shoulders and are sewn over them
    s_out = L["shoulder_x"] * (0.85 if sleeveless else 1.0)
    s_in = L["neck_rx"] + 0.045
    h_neck = h_sh - (0.09 if sleeveless else 0.08)
    side = side_line(L, y0, (w_hem / 2, 0), (w_arm / 2, h_arm), 1.06)
    k = len(side)
    pts = ([(-w_hem / 2, 0), (w_hem / 2, 0)] + side +
           [(w_arm / 2, h_arm), (s_out, h_sh), (s_in, h_sh), (0, h_neck), (-s_in, h_sh), (-s_out, h_sh),
            (-w_arm / 2, h_arm)] + [(-u, v) for u, v in reversed(side)])
    idx = dict(hem_l=0, hem_r=1, armpit_r=2 + k, sh_out_r=3 + k, sh_in_r=4 + k, neck=5 + k, sh_in_l=6 + k,
               sh_out_l=7 + k, armpit_l=8 + k)
    return pts, idx


def torso_seams(i):
    return [
        ("front", i["hem_r"], i["armpit_r"], "back", i["hem_l"], i["armpit_l"], "right side seam (+x), hem to armpit"),
        ("front", i["hem_l"], i["armpit_l"], "back", i["hem_r"], i["armpit_r"], "left side seam (-x), hem to armpit"),
        ("front", i["sh_out_r"], i["sh_in_r"], "back", i["sh_out_l"], i["sh_in_l"], "right shoulder, outer to inner"),
        ("front", i["sh_out_l"], i["sh_in_l"], "back", i["sh_out_r"], i["sh_in_r"], "left shoulder, outer to inner"),
    ]


def sleeveless_shirt(L):
    y0 = L["hip_y"] - 0.02
    pts, idx = shirt_outline(L, y0)
    R = wrap_radius(max(L["chest_rx"], L["chest_rz"], L["hip_rx"]) + 0.05, max(abs(u) for u, _ in pts))
    t = (L["axis_x"], y0, L["axis_z"])
    return document("sleeveless_shirt", "Sleeveless shirt: front and back panels with shoulder straps, wrapped round the\n"
                    "body's axis, sewn at the sides and over the shoulders. Generated by\n"
                    "scripts/make_patterns.py for %s." % L["name"],
                    [panel("front", pts, t, wrap=R), panel("back", pts, t, BACK, wrap=R)],
                    [seam(*s) for s in torso_seams(idx)])


def dress(L):
    y0 = L["knee_y"] + 0.02
    pts, idx = shirt_outline(L, y0, flare=1.35)
    R = wrap_radius(max(L["chest_rx"], L["hip_rx"]) + 0.07, max(abs(u) for u, _ in pts))
    t = (L["axis_x"], y0, L["axis_z"])
    return document("dress", "Knee-length dress with shoulder straps: a long flared version of the sleeveless\n"
                    "shirt. Generated by scripts/make_patterns.py for %s." % L["name"],
                    [panel("front", pts, t, wrap=R), panel("back", pts, t, BACK, wrap=R)],
                    [seam(*s) for s in torso_seams(idx)])


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def unit(a):
    n = norm(a)
    return tuple(x / n for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def quaternion_from_axes(x, y, z):
    """[qx, qy, qz, qw] of the rotation whose columns are x, y, z (no gimbal lock, unlike rpy)."""
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = 2 * math.sqrt(tr + 1)
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4)
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / s]
    q[i] = s / 4
    q[j] = (m[j][i] + m[i][j]) / s
    q[k] = (m[k][i] + m[i][k]) / s
    return tuple(q)


CAP_POINTS = 6  # outline points on each half of a sleeve cap, besides its ends
# Cap height as a fraction of the armhole's extent along the arm (armpit to the top of the
# shoulder). The full extent over-shoots: the cap's top also comes down the tube's radius and the
# cloth shears round the arm's root. Swept on both bodies at spacings 0.02-0.04 m: 0.5-0.6 sewed
# every T-shirt, 0.3-0.4 and 0.7-1.2 left armhole seams 2-4 cm open at some spacing, a square
# sleeve (0) did on the procedural body.
CAP_FRACTION = 0.55


def cap_curve(half, cap, n=CAP_POINTS):
    """The half-cap from the underarm corner (u = half) to the top (u = 0): v above the underarm
    line = cap * (1 + cos(pi u / half)) / 2; n + 2 points (corner and top included)."""
    return [(half * (1 - k / (n + 1.0)), cap * 0.5 * (1 + math.cos(math.pi * (1 - k / (n + 1.0)))))
            for k in range(n + 2)]


def polyline_length(pts):
    return sum(norm(sub(pts[i + 1], pts[i])) for i in range(len(pts) - 1))


def cap_half_width(armhole, cap):
    """Half-width whose half-cap is as long as the armhole (bisection)."""
    lo, hi = 1e-3, armhole
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if polyline_length(cap_curve(mid, cap)) < armhole:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def sleeve_outline(half, length, cap):
    """0 cuff left, 1 cuff right, 2 underarm corner right (half, length), the cap over the top
    (0, length + cap) to the underarm corner left (-half, length), the last point."""
    right = [(u, length + v) for u, v in cap_curve(half, cap)]
    left = [(-u, v) for u, v in reversed(right[:-1])]
    return [(-half, 0), (half, 0)] + right + left


def tshirt(L):
    y0 = L["hip_y"] - 0.02
    pts, idx = shirt_outline(L, y0, sleeveless=False)
    s_out_t = pts[idx["sh_out_r"]][0]
    R = wrap_radius(max(L["chest_rx"], L["chest_rz"], L["hip_rx"]) + 0.05, max(abs(u) for u, _ in pts))
    t = (L["axis_x"], y0, L["axis_z"])
    panels = [panel("front", pts, t, wrap=R), panel("back", pts, t, BACK, wrap=R)]
    seams = [seam(*s) for s in torso_seams(idx)]
    # Armhole: armpit to shoulder outer on each torso panel.
    armhole = norm(sub(pts[idx["sh_out_r"]], pts[idx["armpit_r"]]))
    ar, sr, al, sl = idx["armpit_r"], idx["sh_out_r"], idx["armpit_l"], idx["sh_out_l"]
    for side, sx in (("right", 1.0), ("left", -1.0)):
        sh = (sx * L["shoulder_joint"][0], L["shoulder_joint"][1], L["shoulder_joint"][2])
        el = (sx * L["elbow"][0], L["elbow"][1], L["elbow"][2])
        axis = unit(sub(sh, el))                 # pose y: from the cuff towards the shoulder
        up = (0.0, 1.0, 0.0)
        zc = unit(sub(up, tuple(axis[i] * sum(up[j] * axis[j] for j in range(3)) for i in range(3))))
        xc = cross(axis, zc)
        # Sleeve cap. The armhole the sleeve is sewn into runs up the side of the torso, from the
        # armpit to the top of the shoulder, nearly in a vertical plane; the arm leaves it
        # slanting down and out. A tube cut square (one length all round) can only meet that
        # slanted loop by stretching its top or tearing the torso's armhole out along the arm:
        # the T-shirt's armhole seams stuck 2 cm open at the armpit and the shoulder. So the cap
        # is cut as a real one: its top (u = 0, on top of the arm) is longer than the underarm
        # by the armhole's extent along the arm, from the armpit seam point to the shoulder point.
        armpit = (sx * L["chest_rx"], L["armpit_y"] - 0.02, L["axis_z"])
        shoulder = (sx * s_out_t, L["shoulder_top_y"], L["axis_z"])
        cap = CAP_FRACTION * max(0.0, sum(sub(shoulder, armpit)[i] * axis[i] for i in range(3)))
        # The sleeve starts on the upper arm clear of the torso (the underarm end of its cap 45%
        # of the way from the shoulder joint to the elbow); the armhole seams pull the cap in.
        upper = norm(sub(sh, el))
        length = 0.55 * upper
        cap_base = tuple(sh[i] - axis[i] * 0.45 * upper for i in range(3))
        cuff = tuple(cap_base[i] - axis[i] * length for i in range(3))
        r = L["arm_r"] + 0.035
        # Half the sleeve's width: its half-cap (underarm corner to top) as long as the armhole,
        # and the tube at least 1.5 cm looser than the arm all round.
        half = max(cap_half_width(armhole, cap), math.pi * (L["arm_r"] + 0.015))
        half = min(half, math.pi * r * 0.98)
        spts = sleeve_outline(half, length, cap)
        top, last = (len(spts) + 1) // 2, len(spts) - 1   # cap top (0, length + cap), corner (-half, length)
        panels.append(panel("sleeve_" + side, spts, cuff, quaternion=quaternion_from_axes(xc, axis, zc), wrap=r,
                            comment="%s sleeve: wrapped round the upper arm, u = 0 on top, seam underneath, "
                                    "cap %.1f cm high" % (side, 100 * cap)))
        name = "sleeve_" + side
        seams.append(seam(name, 1, 2, name, 0, last, "%s sleeve: underarm seam, cuff to cap" % side))
        # Local +u of a sleeve points to the body's back on the right arm and to its front on the left.
        if side == "right":
            seams.append(seam("front", ar, sr, name, last, top, "right armhole, front half (after the body is sewn)", 1))
            seams.append(seam("back", al, sl, name, 2, top, "right armhole, back half (after the body is sewn)", 1))
        else:
            seams.append(seam("front", al, sl, name, 2, top, "left armhole, front half (after the body is sewn)", 1))
            seams.append(seam("back", ar, sr, name, last, top, "left armhole, back half (after the body is sewn)", 1))
    return document("tshirt", "T-shirt with short sleeves: the shirt's front and back plus one sleeve per arm,\n"
                    "each sleeve a panel wrapped round the upper arm. Generated by\n"
                    "scripts/make_patterns.py for %s." % L["name"], panels, seams)


def trousers(L):
    y0 = L["ankle_y"] + 0.03
    H = L["waist_y"] - y0
    h_hip = L["hip_y"] - y0
    hc = L["crotch_y"] - y0 - 0.05
    w_ank = math.pi * (L["ankle_r"] + 0.03)        # half the hem circumference
    # Quarter girths: the widest seat between crotch and hips, and the waist (a front or back
    # panel of one leg spans half of the body's front or back above the crotch). The hip landmark
    # is not the widest place, the body stays wide well above it (body_hm08: 0.94 m 5 cm above
    # the hip landmark), and its back is wider there than its front (the seat: 0.52 against
    # 0.44 m on body_hm08), so each panel follows the measured front or back up to the waist.
    # Cut to equal halves, body_hm08's back panels could not reach the sides and the outseams
    # stayed 5 cm open at the top of the hips.

    def outline(part):
        quarter_hip = 0.5 * max_girth(L, L["crotch_y"], L["hip_y"], part) * 1.1
        # The waist over the body by the body's waist ease: at 5% the stiffer cloth (k_structural
        # 100 N/m) held body_hm08's waistband 30-43% stretched over the tops of the hips at the
        # side seams; much looser, the trousers slid down over the hips.
        quarter_waist = 0.5 * girth(L, L["waist_y"], part) * L["waist_ease"]
        w_out_hip, w_in_hip = 0.55 * quarter_hip, 0.45 * quarter_hip
        w_out_waist, w_in_waist = 0.55 * quarter_waist, 0.45 * quarter_waist
        # Crotch point: at least 5 cm past the inner hip line, and far enough that the front and
        # the back rise (centre line, waist to crotch) together span the body's crotch loop
        # (measure_rise): shorter, the crotch seams stayed 2-3 cm apart under the body.
        w_cr = max(w_in_hip + 0.05, w_in_waist + math.sqrt(max(0.0, (0.5 * L["rise"]) ** 2 - (H - hc) ** 2)))

        def inner(v):  # the centre line's |u| from the crotch point up to the waist centre
            return w_cr + (w_in_waist - w_cr) * (v - hc) / (H - hc)
        side = fit_side(L, y0, (w_out_hip, h_hip), (w_out_waist, H),
                        lambda y: 1.06 * girth(L, y, part) / 2 - inner(y - y0))
        # Outer side at +u: 0 hem-in, 1 hem-out, 2 hip-out, (points up the outseam,) waist-out,
        # centre (waist), crotch.
        return ([(-w_ank / 2, 0), (w_ank / 2, 0), (w_out_hip, h_hip)] + side +
                [(w_out_waist, H), (-w_in_waist, H), (-w_cr, hc)])
    right = {part: outline("larger") for part in ("front", "back")}
    # Mirrored (outer side at -u), order reversed: point i of `right` is point n-1-i of `left`.
    left = {part: mirror(pts) for part, pts in right.items()}
    R = L["thigh_r"] + 0.05
    panels = []
    for leg, sx in (("right", 1.0), ("left", -1.0)):
        # Each leg's panels wrap round the leg's own axis, from the ankle up through the hip joint
        # (legs apart in the pose lean outwards).
        hip = (sx * L["hip_joint"][0], L["hip_joint"][1], L["hip_joint"][2])
        ank = (sx * L["ankle"][0], L["ankle"][1], L["ankle"][2])
        axis = unit(sub(hip, ank))
        front = (0.0, 0.0, 1.0)
        zc = unit(sub(front, tuple(axis[i] * sum(front[j] * axis[j] for j in range(3)) for i in range(3))))
        xc = cross(axis, zc)
        t = tuple(ank[i] + axis[i] * (y0 - L["ankle_y"]) / axis[1] for i in range(3))
        t = (t[0] + L["axis_x"], t[1], t[2])
        back_axes = (tuple(-c for c in xc), axis, tuple(-c for c in zc))  # half a turn about the leg
        # Front panels face +z; back panels are turned half a turn, which mirrors u in the world.
        panels.append(panel("front_" + leg, right["front"] if sx > 0 else left["front"], t, wrap=R,
                            quaternion=quaternion_from_axes(xc, axis, zc)))
        panels.append(panel("back_" + leg, left["back"] if sx > 0 else right["back"], t, wrap=R,
                            quaternion=quaternion_from_axes(*back_axes)))

    def at(part, name, mirrored):
        n = len(right[part])
        i = {"hem_in": 0, "hem_out": 1, "hip_out": 2, "waist_out": n - 3, "centre": n - 2, "crotch": n - 1}[name]
        return n - 1 - i if mirrored else i

    def sew(a, b, fr, to, comment):
        # a, b: (panel, part, mirrored); the stretch from point fr to point to on both, in pieces
        # of at most 3 outline edges (a stretch must stay under half the outline). Front and
        # back outlines have the same points on the outseam.
        def walk(part, mirrored):
            # The shorter way round on the unmirrored outline (up the outseam on a tie), the
            # same points in reverse order on a mirrored one.
            n = len(right[part])
            i, j = at(part, fr, False), at(part, to, False)
            step = 1 if (j - i) % n <= (i - j) % n else -1
            steps = min((j - i) % n, (i - j) % n)
            if mirrored:
                i, step = n - 1 - i, -step
            return lambda k: (i + step * k) % n, steps
        on_a, steps = walk(a[1], a[2])
        on_b, _ = walk(b[1], b[2])
        pieces = max(1, (steps + 2) // 3)
        out = []
        for q in range(pieces):
            k0, k1 = steps * q // pieces, steps * (q + 1) // pieces
            out.append(seam(a[0], on_a(k0), on_a(k1), b[0], on_b(k0), on_b(k1),
                            comment + ("" if pieces == 1 else " (%d of %d)" % (q + 1, pieces))))
        return "\n".join(out)
    fr, br = ("front_right", "front", False), ("back_right", "back", True)
    fl, bl = ("front_left", "front", True), ("back_left", "back", False)
    seams = [
        sew(fr, br, "hem_out", "hip_out", "right outseam, hem to hip"),
        sew(fr, br, "hip_out", "waist_out", "right outseam, hip to waist"),
        sew(fr, br, "hem_in", "crotch", "right inseam, hem to crotch"),
        sew(fl, bl, "hem_out", "hip_out", "left outseam, hem to hip"),
        sew(fl, bl, "hip_out", "waist_out", "left outseam, hip to waist"),
        sew(fl, bl, "hem_in", "crotch", "left inseam, hem to crotch"),
        sew(fr, fl, "centre", "crotch", "centre front, waist to crotch"),
        sew(br, bl, "centre", "crotch", "centre back, waist to crotch"),
    ]
    return document("trousers", "Long trousers: a front and a back panel per leg, wrapped round the leg's axis,\n"
                    "sewn along the outseams, inseams and the centre front and back.\n"
                    "Generated by scripts/make_patterns.py for %s." % L["name"], panels, seams)


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--measure":
        # --measure BODY.obj Y0 Y1 [STEP]: print a girth table for a landmark set.
        y0, y1 = float(sys.argv[3]), float(sys.argv[4])
        step = float(sys.argv[5]) if len(sys.argv) > 5 else 0.02
        ys = [round(y0 + step * k, 4) for k in range(int(round((y1 - y0) / step)) + 1)]
        print(measure_girths(sys.argv[2], ys))
        return
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config", "patterns")
    for L in (HM08, PROCEDURAL):
        if L is None:
            continue
        out = os.path.join(root, L["name"])
        os.makedirs(out, exist_ok=True)
        for make in (skirt, trousers, sleeveless_shirt, tshirt, dress):
            path = os.path.join(out, make.__name__ + ".yaml")
            with open(path, "w") as f:
                f.write(make(L))
            print("wrote", os.path.relpath(path))


if __name__ == "__main__":
    main()
