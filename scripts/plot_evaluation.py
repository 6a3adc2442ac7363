#!/usr/bin/python3
"""Turns the evaluation's CSV files (written by the `evaluate` program) into PNG plots and
report.md in the same folder, and prints the report's path.

Usage: /usr/bin/python3 scripts/plot_evaluation.py OUT_DIR

Needs only Debian's python3-matplotlib (and numpy, which it pulls in); the Agg backend, no display.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

OUT = sys.argv[1] if len(sys.argv) > 1 else "evaluation"
METHOD_STYLE = {
    "ours": ("tab:blue", "resolver + shape relaxation (ours, objective smooth)"),
    "paper": ("tab:green", "resolver, the paper's formulation (objective paper)"),
    "per_stencil": ("tab:orange", "baseline: per-stencil projection"),
    "push_out": ("tab:red", "baseline: vertex push-out"),
}
plt.rcParams.update({"figure.dpi": 100, "font.size": 9, "axes.grid": True, "grid.alpha": 0.3})


def read(name):
    path = os.path.join(OUT, name)
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def fmt(x, digits=3):
    """A number for a table: integers as such, others with `digits` significant digits."""
    v = num(x)
    if math.isnan(v):
        return "-"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v == int(v) and abs(v) < 1e7:
        return str(int(v))
    return f"{v:.{digits}g}"


def ms(x):
    return fmt(1e3 * num(x))


def mm(x):
    return fmt(1e3 * num(x))


def yes(x):
    return "yes" if str(x) in ("1", "true", "True") else "no"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        lines.append("| " + " | ".join(str(c).replace("|", "/") for c in r) + " |")
    return "\n".join(lines)


def save(fig, name, rect=None):
    fig.tight_layout(rect=rect)
    fig.savefig(os.path.join(OUT, name))
    plt.close(fig)
    return name


summary = {}
if os.path.exists(os.path.join(OUT, "summary.json")):
    with open(os.path.join(OUT, "summary.json")) as f:
        summary = json.load(f)

report = []
images = []


def image(name, caption):
    images.append(name)
    report.append(f"![{caption}]({name})\n")


# ------------------------------------------------------------------------------------------------
# 1. Resolver: error against iterations and wall time.
trace = read("resolver_trace.csv")
rtable = read("resolver_table.csv")
scenes = []
for r in rtable:
    if r["scene"] not in scenes:
        scenes.append(r["scene"])


def scene_plot(scene):
    rows = [r for r in trace if r["scene"] == scene]
    info = next(r for r in rtable if r["scene"] == scene)
    fig, axes = plt.subplots(2, 3, figsize=(13, 7))
    for method, (color, label) in METHOD_STYLE.items():
        rs = [r for r in rows if r["method"] == method]
        if not rs:
            continue
        it = [num(r["iteration"]) for r in rs]
        t = [1e3 * num(r["seconds"]) for r in rs]
        g = [num(r["garment_edge_crossings"]) for r in rs]
        b = [num(r["body_edge_crossings"]) for r in rs]
        ins = [num(r["vertices_inside"]) for r in rs]
        dep = [1e3 * num(r["max_depth_m"]) for r in rs]
        for row, x in enumerate((it, t)):
            ax = axes[row]
            # A state exists only at the marked steps: hold each value until the next one.
            kw = dict(color=color, ms=3.5, drawstyle="steps-post")
            ax[0].plot(x, g, "-o", **kw)
            ax[0].plot(x, b, "--s", **kw)
            ax[1].plot(x, ins, "-o", **kw)
            ax[2].plot(x, dep, "-o", **kw)
    for row, xl in enumerate(("iteration (detect-solve rounds; push-out: its one pass)", "wall time (ms)")):
        ax = axes[row]
        ax[0].set_ylabel("edge-face crossings left")
        ax[0].set_yscale("symlog", linthresh=1)
        ax[1].set_ylabel("garment vertices inside the body")
        ax[1].set_yscale("symlog", linthresh=1)
        ax[2].set_ylabel("deepest inside vertex (mm)")
        for a in ax:
            a.set_xlabel(xl)
            a.set_ylim(bottom=0)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=c, marker="o", label=l) for c, l in METHOD_STYLE.values()]
    handles += [Line2D([], [], color="k", ls="-", marker="o", ms=3.5, label="garment edges through body faces"),
                Line2D([], [], color="k", ls="--", marker="s", ms=3.5, label="body edges through garment faces (crossings panels)")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(f"{scene}: {info['garment_vertices']} garment vertices, {info['body_faces']} body faces "
                 "(errors counted by the independent referee after every step)", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(OUT, f"resolver_{scene}.png"))
    plt.close(fig)
    return f"resolver_{scene}.png"


def resolver_overview():
    fig, ax = plt.subplots(figsize=(9, 5.5))
    markers = "osD^vP*Xh"
    for i, scene in enumerate(scenes):
        for method, (color, label) in METHOD_STYLE.items():
            r = next((r for r in rtable if r["scene"] == scene and r["method"] == method), None)
            if r is None:
                continue
            err = num(r["garment_edge_after"]) + num(r["body_edge_after"]) + num(r["inside_after"])
            ax.scatter(1e3 * num(r["time_median_s"]), err, color=color, marker=markers[i % len(markers)], s=50,
                       label=label if i == 0 else None, edgecolor="k", linewidth=0.5)
    for i, scene in enumerate(scenes):
        ax.scatter([], [], color="grey", marker=markers[i % len(markers)], label=f"scene: {scene}")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1)
    top = max([num(r["garment_edge_after"]) + num(r["body_edge_after"]) + num(r["inside_after"]) for r in rtable] + [1])
    ax.set_ylim(-0.5, 3 * top)
    ax.set_xlabel("wall time per call, median (ms)")
    ax.set_ylabel("error left: crossings (both directions) + vertices inside")
    ax.set_title("Resolver against baselines: error left against run time (same input, same process)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return save(fig, "resolver_overview.png")


def resolver_strain():
    """Largest and 99th-percentile edge strain against run time, per method and scene."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharex=True)
    markers = "osD^vP*Xh"
    for ax, key, title in ((axes[0], "max_strain", "largest edge strain"), (axes[1], "p99_strain", "99th-percentile edge strain")):
        for i, scene in enumerate(scenes):
            for method, (color, label) in METHOD_STYLE.items():
                r = next((r for r in rtable if r["scene"] == scene and r["method"] == method), None)
                if r is None or key not in r:
                    continue
                ax.scatter(1e3 * num(r["time_median_s"]), num(r[key]), color=color, marker=markers[i % len(markers)],
                           s=50, label=label if i == 0 else None, edgecolor="k", linewidth=0.5)
        if key == "max_strain":
            ax.axhline(0.3, color="k", linestyle=":", linewidth=1, label="target 0.3")
        ax.set_yscale("log")  # a sliver edge of a procedural garment can stretch many times
        ax.set_xscale("log")
        ax.set_xlabel("wall time per call, median (ms)")
        ax.set_ylabel(f"{title} |l / l0 - 1| against the input")
        ax.set_title(f"{title} against run time")
    for i, scene in enumerate(scenes):
        axes[1].scatter([], [], color="grey", marker=markers[i % len(markers)], label=f"scene: {scene}")
    axes[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[0].legend(fontsize=7, loc="upper left")
    return save(fig, "resolver_strain.png")


report.append("# Evaluation report\n")
report.append(
    f"Mode: **{summary.get('mode', '?')}**. Written {summary.get('date', '?')} on {summary.get('machine', '?')}; "
    f"load average {summary.get('load_average_start', '?')} at the start and {summary.get('load_average_end', '?')} "
    f"at the end (the machine was shared: wall times are noisy). Shared data: "
    f"{'used from ' + summary.get('data_dir', '') if summary.get('data_found') else 'not used'}. "
    f"Total {fmt(summary.get('seconds.total'))} s.\n")
for n in summary.get("notes", []):
    report.append(f"- Note: {n}")
report.append("")
report.append("Reproduce: `scripts/evaluate.sh [OUT_DIR]` (full; the shared meshes from `$VT_DATA` or "
              "`../shared/data` when present) or `scripts/evaluate.sh --quick [OUT_DIR]` (procedural scenes only). "
              "Every number below comes from the CSV files beside this report.\n")

report.append("## Key numbers\n")
key = []
if rtable:
    key.append(("our resolver leaves no crossing and no vertex inside (independent count), every scene",
                yes(summary.get("resolver.ours_clean_all") in (True, 1))))
if "resolver.ours_worst_median_ms_body_hm08" in summary:
    key.append(("our resolver, slowest body_hm08 garment, median ms", fmt(summary["resolver.ours_worst_median_ms_body_hm08"])))
for k, label in (("stability.automatic_dt_stable_in_every_cell", "automatic dt stable in every stiffness cell"),
                 ("stability.paper_bound_unstable_somewhere", "the paper's eq. 4 bound (stiffest spring) blows up somewhere"),
                 ("stability.zone_solves_finite_and_bounded", "zone solves finite, displacement bounded (ill-conditioned zones)")):
    if k in summary:
        key.append((label, yes(summary[k] in (True, 1))))
if "stability.measured_edge_factor_min" in summary:
    key.append(("measured stability edge, dt / eq. 4 bound (min-max over K/m)",
                f"{fmt(summary['stability.measured_edge_factor_min'])}-{fmt(summary['stability.measured_edge_factor_max'])}"))
    key.append(("automatic dt / eq. 4 bound", fmt(summary.get("stability.automatic_factor_max"))))
if "extreme.cases" in summary:
    key.append(("extreme cases: converged / run; any crash or hang",
                f"{fmt(summary['extreme.converged'])} / {fmt(summary['extreme.cases'])}; "
                f"{'none' if summary.get('extreme.no_crash_no_hang') else 'YES'}"))
if "lean.resolve_second_call_s" in summary:
    key.append(("resolve: first call (BVH built) / second call on the same body, ms",
                f"{ms(summary['lean.resolve_first_call_s'])} / {ms(summary['lean.resolve_second_call_s'])}"
                + (f" (BVH {ms(summary['lean.resolve_bvh_build_s'])})" if "lean.resolve_bvh_build_s" in summary else "")))
_few = read("lean_few.csv")
if _few:
    _per = [1e3 * num(r["after_first_pass_min_s"]) / num(r["penetrating_vertices"]) for r in _few
            if num(r["penetrating_vertices"]) >= 8]
    _sizes = sorted({int(num(r["garment_vertices"])) for r in _few})
    if _per:
        key.append((f"resolve, after the first pass: ms per penetrating vertex (k >= 8; garments {_sizes[0]}-{_sizes[-1]} vertices)",
                    f"{fmt(min(_per))}-{fmt(max(_per))}"))
if "lean.drape_map_renders_after_two_drapes" in summary:
    key.append(("depth-map renders after two drapes on one body", fmt(summary["lean.drape_map_renders_after_two_drapes"])))
report.append(table(["what", "value"], key))
report.append("")

if rtable:
    report.append("## 1. Resolver: error against run time\n")
    report.append(
        "Four methods run side by side on the same input in the same process (each body's BVH built once "
        "before, not timed):\n\n"
        "- **ours**: the resolver (Sun et al. 2016: edge-face crossings both ways, stencils, impact zones "
        "solved for the minimum displacement with lambda >= 0, iterate), then the shape relaxation (the "
        "moved region and its rings share the move, edges keep their input vectors, turned by their ends' "
        "local rotations (as-rigid-as-possible), as far as the body allows, no crossing comes back);\n"
        "- **paper**: the same rounds alone, the paper's formulation (objective paper);\n"
        "- **baseline: per-stencil projection**: the same resolver with the impact-zone solve replaced by "
        "independent projection of every stencil (a vertex moved by several gets their mean);\n"
        "- **baseline: vertex push-out**, the post-processing of learned garment models: each garment vertex "
        "inside the body moves to its nearest body point plus a margin (the same clearance) along that "
        "face's normal; vertices only, no edge test.\n\n"
        "Errors are counted by an independent referee (Moller-Trumbore segment tests and three-ray parity "
        "through its own AABB trees; no FCL, no code of the resolver's detector) after every step; the time "
        "spent counting is left out of the wall-time axis. Shape against the input, by the same referee: "
        "edge strain |l / l0 - 1| (max and 99th percentile), displacement, the need (the least lift any "
        "resolver must make: the deepest input vertex inside, or the farthest outer end of a body edge "
        "beyond an input garment face it crosses), and vertices that started more than 1 cm from the body "
        "and moved more than 1 mm. The table's time is the median of "
        f"{rtable[0]['runs']} calls without the observer.\n")
    rows = []
    for r in rtable:
        rows.append([
            r["scene"], METHOD_STYLE[r["method"]][1],
            f"{r['garment_edge_before']} / {r['body_edge_before']} / {r['inside_before']}",
            f"**{r['garment_edge_after']} / {r['body_edge_after']} / {r['inside_after']}**",
            mm(r["max_depth_after_m"]),
            f"{mm(r['mean_displacement_m'])} / {mm(r['max_displacement_m'])}",
            f"{fmt(num(r['max_strain']))} / {fmt(num(r['p99_strain']))}",
            f"{mm(r['need_m'])}", r["far_vertices_moved"],
            f"{ms(r['time_median_s'])} ({ms(r['time_min_s'])}-{ms(r['time_max_s'])})",
            r["iterations"], "one pass" if r["method"] == "push_out" else yes(r["converged"]),
        ])
    report.append(table(["scene", "method", "before: crossings garment-edge / body-edge / inside",
                         "after (independent)", "deepest left mm", "displacement mean / max mm",
                         "edge strain max / p99", "need mm", "far vertices moved",
                         "time ms median (min-max)", "iterations", "converged"], rows))
    report.append("")
    for r in rtable:
        if r["method"] != "push_out" and r["converged"] not in ("1",):
            report.append(f"- {r['scene']}, {METHOD_STYLE[r['method']][1]}: {r['reason']}")
    report.append("")

    def left(r):
        return num(r["garment_edge_after"]) + num(r["body_edge_after"]) + num(r["inside_after"])

    def by(method):
        return {r["scene"]: r for r in rtable if r["method"] == method}

    ours, per, push = by("ours"), by("per_stencil"), by("push_out")
    findings = []
    findings.append(f"Ours leaves no crossing and no vertex inside on {sum(left(r) == 0 for r in ours.values())} of "
                    f"{len(ours)} scenes.")
    if push:
        bad = [sc for sc, r in push.items() if left(r) > 0]
        worst = max(push.values(), key=left)
        inside_left = sum(num(r["inside_after"]) > 0 for r in push.values())
        findings.append(f"The vertex push-out leaves vertices inside on {inside_left} and edge crossings on {len(bad)} "
                        f"of {len(push)} scenes (worst: {worst['scene']}, {worst['garment_edge_after']} garment edges "
                        f"through the body and {worst['body_edge_after']} body edges through the garment): a vertex "
                        "test cannot see an edge or a face passing through. It costs a median "
                        f"{fmt(np.median([num(push[s]['time_median_s']) / num(ours[s]['time_median_s']) for s in push if s in ours]))} "
                        "of our time.")
    if per:
        conv = sum(r["converged"] == "1" and left(r) == 0 for r in per.values())
        it_ratio = np.median([num(per[s]["iterations"]) / max(num(ours[s]["iterations"]), 1) for s in per if s in ours])
        t_ratio = np.median([num(per[s]["time_median_s"]) / num(ours[s]["time_median_s"]) for s in per if s in ours])
        findings.append(f"Per-stencil projection reaches zero on {conv} of {len(per)} scenes but needs a median "
                        f"{fmt(it_ratio)} times the iterations and {fmt(t_ratio)} times the time of the zone solve: "
                        "averaging moves a vertex that several stencils share by less than they ask together, so "
                        "the penetration front advances in smaller steps.")
    report.append(" ".join(findings) + "\n")
    image(resolver_overview(), "error left against time per call")
    image(resolver_strain(), "edge strain against time per call")
    for scene in scenes:
        image(scene_plot(scene), f"resolver on {scene}")

# ------------------------------------------------------------------------------------------------
# 2. Drape.
maps = read("drape_map_size.csv")
modes = read("drape_modes.csv")
spacing = read("drape_spacing.csv")
dts = read("drape_dt.csv")
if maps or modes or spacing or dts:
    report.append("## 2. Drape: error against run time\n")
    report.append(
        "Collision error is measured on the garment as the drape leaves it, before the resolver pass, "
        "against the body mesh (referee: vertices inside by three-ray parity, depth = distance to the "
        "nearest body triangle), not against the depth maps. Defaults otherwise (tol 5 mm, automatic dt).\n")

if maps:
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.6))
    for body in sorted({r["body"] for r in maps}):
        rs = sorted([r for r in maps if r["body"] == body], key=lambda r: num(r["map_pixels"]))
        x = [num(r["map_pixels"]) for r in rs]
        line, = a.plot(x, [1e3 * num(r["max_depth_m"]) for r in rs], "-o", label=f"{body}: deepest vertex inside")
        a.plot(x, [-1e3 * num(r["signed_distance_p05_m"]) for r in rs], "--s", color=line.get_color(),
               label=f"{body}: 5th percentile of the signed distance, negated")
        a.plot(x, [-1e3 * num(r["median_gap_m"]) for r in rs], ":^", color=line.get_color(),
               label=f"{body}: median distance of the vertices outside, negated")
        line, = b.plot(x, [1e3 * num(r["seconds_per_iteration"]) for r in rs], "-o", label=f"{body}: time per iteration")
        b.plot(x, [1e3 * num(r["setup_s"]) for r in rs], "--s", color=line.get_color(), label=f"{body}: setup (map render)")
        for r in rs:
            if r["map_size"] == "0":
                a.annotate("from tol", (num(r["map_pixels"]), 1e3 * num(r["max_depth_m"])), fontsize=7,
                           xytext=(3, 6), textcoords="offset points")
    a.axhline(0, color="k", lw=0.8)
    a.set_xscale("log", base=2)
    b.set_xscale("log", base=2)
    b.set_yscale("log")
    a.set_xlabel("depth map size, longer side (pixels)")
    b.set_xlabel("depth map size, longer side (pixels)")
    a.set_ylabel("depth inside the body mesh (mm); below 0: clear of it")
    b.set_ylabel("time (ms)")
    a.set_title("Collision error against map size (before the resolver)")
    b.set_title("Cost against map size")
    lo, hi = a.get_ylim()
    a.set_ylim(lo - 0.6 * (hi - lo), hi + 0.1 * (hi - lo))
    a.legend(fontsize=7, loc="lower right")
    b.legend(fontsize=7)
    report.append("### Map size\n")
    report.append(table(["body", "garment", "vertices", "map px (requested)", "pixel mm", "iterations", "converged",
                         "ms/iteration", "setup ms", "total s", "inside", "deepest mm", "5% signed distance mm",
                         "median gap mm"],
                        [[r["body"], r["garment"], r["vertices"], f"{r['map_pixels']} ({r['map_size'] if r['map_size'] != '0' else 'from tol'})",
                          mm(r["pixel_m"]), r["iterations"], yes(r["converged"]), ms(r["seconds_per_iteration"]),
                          ms(r["setup_s"]), fmt(r["total_s"]), r["inside"], mm(r["max_depth_m"]),
                          mm(r["signed_distance_p05_m"]), mm(r["median_gap_m"])]
                         for r in maps]))
    report.append("")
    image(save(fig, "drape_map_size.png"), "map size")
    ranges = "; ".join(
        f"{b}: {fmt(min(1e3 * num(r['seconds_per_iteration']) for r in maps if r['body'] == b))}-"
        f"{fmt(max(1e3 * num(r['seconds_per_iteration']) for r in maps if r['body'] == b))} ms"
        for b in sorted({r["body"] for r in maps}))
    report.append(f"Deepest vertex inside the body mesh at any map size: {fmt(max(1e3 * num(r['max_depth_m']) for r in maps))} mm "
                  f"(at most {max(int(num(r['inside'])) for r in maps)} vertices inside). Time per iteration over the map "
                  f"sizes ({ranges}); the render grows from {ms(min(num(r['setup_s']) for r in maps))} to "
                  f"{ms(max(num(r['setup_s']) for r in maps))} ms and is paid once per body. Runs that did not settle "
                  "within the iteration limit are marked in the table.\n")

if modes:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    bodies = sorted({r["body"] for r in modes})
    w = 0.38
    for i, mode in enumerate(("image", "object")):
        rs = [next((r for r in modes if r["body"] == b and r["mode"] == mode), None) for b in bodies]
        x = np.arange(len(bodies)) + (i - 0.5) * w
        lab = "image space (depth maps)" if mode == "image" else "object space (nearest body point)"
        axes[0].bar(x, [1e3 * num(r["seconds_per_iteration"]) if r else 0 for r in rs], w, label=lab)
        axes[1].bar(x, [num(r["total_s"]) if r else 0 for r in rs], w, label=lab)
        axes[2].bar(x, [1e3 * num(r["median_gap_m"]) if r else 0 for r in rs], w, label=lab)
        for xi, r in zip(x, rs):
            if r:
                axes[2].annotate(f"{r['inside']} inside,\n{mm(r['max_depth_m'])} mm deep", (xi, 1e3 * num(r["median_gap_m"])),
                                 ha="center", va="bottom", fontsize=7)
    for ax, yl in zip(axes, ("time per iteration (ms)", "drape + resolver, total (s)",
                             "median distance to the body before the resolver (mm)")):
        ax.set_xticks(np.arange(len(bodies)))
        ax.set_xticklabels(bodies)
        ax.set_ylabel(yl)
        ax.set_xlabel("body")
    axes[0].set_yscale("log")
    axes[1].set_yscale("log")
    axes[2].set_ylim(0, axes[2].get_ylim()[1] * 1.15)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.suptitle("Image space against object space, the same garment and iteration cap", fontsize=10)
    report.append("### Image space against object space (nearest body point)\n")
    report.append(table(["body", "garment", "vertices", "mode", "iterations", "converged", "ms/iteration",
                         "drape s", "resolver s", "total s", "inside before resolver", "deepest mm", "median gap mm",
                         "after resolver: crossings / inside"],
                        [[r["body"], r["garment"], r["vertices"], r["mode"], r["iterations"], yes(r["converged"]),
                          ms(r["seconds_per_iteration"]), fmt(r["drape_total_s"]), fmt(r["resolve_s"]), fmt(r["total_s"]),
                          r["inside"], mm(r["max_depth_m"]), mm(r["median_gap_m"]),
                          f"{r['crossings_after_resolve']} / {r['inside_after_resolve']}"]
                         for r in modes]))
    report.append("")
    image(save(fig, "drape_modes.png", rect=(0, 0.06, 1, 1)), "image against object space")
    for body in bodies:
        im = next((r for r in modes if r["body"] == body and r["mode"] == "image"), None)
        ob = next((r for r in modes if r["body"] == body and r["mode"] == "object"), None)
        if im and ob:
            report.append(f"- {body}: object space costs {fmt(num(ob['seconds_per_iteration']) / num(im['seconds_per_iteration']))} "
                          f"times the time per iteration of the maps ({ms(ob['seconds_per_iteration'])} against "
                          f"{ms(im['seconds_per_iteration'])} ms) and {fmt(num(ob['total_s']) / num(im['total_s']))} times "
                          f"the total; median gap {mm(ob['median_gap_m'])} against {mm(im['median_gap_m'])} mm, "
                          f"deepest vertex inside {mm(ob['max_depth_m'])} against {mm(im['max_depth_m'])} mm.")
    report.append("")

if spacing:
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
    for body in sorted({r["body"] for r in spacing}):
        rs = sorted([r for r in spacing if r["body"] == body], key=lambda r: num(r["vertices"]))
        x = [num(r["vertices"]) for r in rs]
        a.plot(x, [1e3 * num(r["seconds_per_iteration"]) for r in rs], "-o", label=f"{body}: ms per iteration")
        a.plot(x, [1e3 * num(r["total_s"]) for r in rs], "--s", label=f"{body}: whole drape (ms)")
        b.plot(x, [num(r["strain_max"]) for r in rs], "-o", label=f"{body}: max strain")
        b.plot(x, [num(r["strain_mean"]) for r in rs], "--s", label=f"{body}: mean strain")
    a.set_xscale("log")
    a.set_yscale("log")
    b.set_xscale("log")
    a.set_xlabel("garment vertices (grid spacing 5 cm ... 1.2 cm)")
    b.set_xlabel("garment vertices")
    a.set_ylabel("time (ms)")
    b.set_ylabel("final strain |l / l0 - 1|, structural springs")
    a.set_title("Time against grid size")
    b.set_title("Final strain against grid size")
    a.legend(fontsize=7)
    b.legend(fontsize=7)
    report.append("### Grid spacing\n")
    report.append(table(["body", "garment", "spacing m", "vertices", "iterations", "converged", "ms/iteration",
                         "total s", "strain max / mean", "inside", "deepest mm", "median gap mm"],
                        [[r["body"], r["garment"], r["spacing_m"], r["vertices"], r["iterations"], yes(r["converged"]),
                          ms(r["seconds_per_iteration"]), fmt(r["total_s"]),
                          f"{fmt(r['strain_max'])} / {fmt(r['strain_mean'])}", r["inside"], mm(r["max_depth_m"]),
                          mm(r["median_gap_m"])]
                         for r in spacing]))
    report.append("")
    image(save(fig, "drape_spacing.png"), "grid spacing")
    for body in sorted({r["body"] for r in spacing}):
        rs = [r for r in spacing if r["body"] == body]
        us = [1e6 * num(r["seconds_per_iteration"]) / num(r["vertices"]) for r in rs]
        report.append(f"- {body}: {fmt(min(us))}-{fmt(max(us))} us per vertex per iteration from "
                      f"{min(int(num(r['vertices'])) for r in rs)} to {max(int(num(r['vertices'])) for r in rs)} vertices; "
                      f"mean strain {fmt(min(num(r['strain_mean']) for r in rs))}-{fmt(max(num(r['strain_mean']) for r in rs))}, "
                      f"max strain {fmt(min(num(r['strain_max']) for r in rs))}-{fmt(max(num(r['strain_max']) for r in rs))}.")
    report.append("")

if dts:
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.5))
    for body in sorted({r["body"] for r in dts}):
        rs = sorted([r for r in dts if r["body"] == body], key=lambda r: num(r["dt_fraction"]))
        x = [num(r["dt_fraction"]) for r in rs]
        conv = [r["converged"] == "1" for r in rs]
        wall = [num(r["wall_s"]) for r in rs]
        sim = [num(r["simulated_s"]) for r in rs]
        l1, = a.plot(x, wall, "-", label=f"{body}: wall time")
        a.plot(x, sim, "--", color=l1.get_color(), label=f"{body}: simulated time")
        for xi, w_, s_, ok in zip(x, wall, sim, conv):
            a.plot(xi, w_, "o", color=l1.get_color(), mfc=l1.get_color() if ok else "white")
            a.plot(xi, s_, "s", color=l1.get_color(), mfc=l1.get_color() if ok else "white")
        l2, = b.plot(x, [1e3 * num(r["max_depth_m"]) for r in rs], "-o", label=f"{body}: deepest vertex inside")
        b.plot(x, [1e3 * num(r["median_gap_m"]) for r in rs], "--s", color=l2.get_color(),
               label=f"{body}: median distance of the vertices outside")
        c.plot(x, [100 * num(r["strain_max"]) for r in rs], "-o", label=f"{body}")
    a.set_yscale("log")
    for ax in (a, b, c):
        ax.set_xlabel("dt / stability bound (eq. 4, per node)")
    a.set_ylabel("time to settle (s); hollow marker: did not settle")
    b.set_ylabel("distance (mm), before the resolver")
    c.set_ylabel("max strain of the structural springs (%)")
    a.set_title("Time to settle against the time step")
    b.set_title("Collision error against the time step")
    c.set_title("Strain against the time step")
    a.legend(fontsize=7)
    b.legend(fontsize=7)
    c.legend(fontsize=7)
    report.append("### Time step\n")
    report.append(table(["body", "garment", "vertices", "dt / bound", "dt ms", "iterations", "simulated s", "wall s",
                         "converged", "inside", "deepest mm", "median gap mm", "max strain"],
                        [[r["body"], r["garment"], r["vertices"], r["dt_fraction"], ms(r["dt_s"]), r["iterations"],
                          fmt(r["simulated_s"]), fmt(r["wall_s"]), yes(r["converged"]), r["inside"],
                          mm(r["max_depth_m"]), mm(r["median_gap_m"]), fmt(r["strain_max"])] for r in dts]))
    report.append("")
    not_conv = [r for r in dts if r["converged"] != "1"]
    for r in not_conv:
        report.append(f"- {r['body']} {r['garment']} at dt {r['dt_fraction']} of the bound: {r['message']}")
    report.append("")
    image(save(fig, "drape_dt.png"), "time step")

# ------------------------------------------------------------------------------------------------
# 3. Stability.
cells = read("stability_cloth.csv")
edges = read("stability_edges.csv")
zones = read("stability_zones.csv")
szones = read("stability_scene_zones.csv")
if cells:
    report.append("## 3. Stability on stiff cases\n")
    report.append(
        "A 0.3 m square of cloth (3 cm grid, 121 nodes, every node nudged by 1e-4 of the spacing) hangs "
        "from its top row under gravity with the default damping and velocity fix. Stiffness K (the "
        "structural springs; shear 0.2 K, flexion 0.1 K) runs from 1e2 to 1e6 times the node mass; dt from "
        "0.1 to 2 times the paper's eq. 4 bound 0.4 pi sqrt(m / K) with K the stiffest single spring. A cell "
        "blew up when a step gave a non-finite value or a node faster than 50 m/s, or when the energy "
        "(kinetic + springs + gravity) rose above its start by more than 1e-3 m g side. The measured edge is "
        "found by bisection; 'automatic' is the drape's dt, 0.9 of the per-node bound (K = sum of the "
        "stiffnesses meeting at a node).\n")
    kms = sorted({num(r["k_over_m_per_s2"]) for r in cells})
    grid = [r for r in cells if r["automatic"] == "0"]
    fs = sorted({num(r["dt_factor"]) for r in grid})
    fig, ax = plt.subplots(figsize=(9, 6.5))
    strain = np.full((len(kms), len(fs)), np.nan)
    for r in grid:
        i, j = kms.index(num(r["k_over_m_per_s2"])), fs.index(num(r["dt_factor"]))
        if r["stable"] == "1":
            strain[i, j] = max(num(r["max_strain"]), 1e-6)
    fe = np.array(fs)
    fedges = np.concatenate(([fe[0] - (fe[1] - fe[0]) / 2 if len(fe) > 1 else fe[0] * 0.5],
                             (fe[:-1] + fe[1:]) / 2,
                             [fe[-1] + (fe[-1] - fe[-2]) / 2 if len(fe) > 1 else fe[0] * 1.5]))
    le = np.log10(np.array(kms))
    kedges = 10 ** np.concatenate(([le[0] - (le[1] - le[0]) / 2 if len(le) > 1 else le[0] - 0.5],
                                   (le[:-1] + le[1:]) / 2,
                                   [le[-1] + (le[-1] - le[-2]) / 2 if len(le) > 1 else le[0] + 0.5]))
    from matplotlib.colors import LogNorm
    finite = strain[np.isfinite(strain)]
    norm = LogNorm(vmin=max(finite.min(), 1e-4), vmax=max(finite.max(), 1e-3)) if finite.size else None
    ax.grid(False)
    pc = ax.pcolormesh(fedges, kedges, np.ma.masked_invalid(strain), cmap="viridis", norm=norm, shading="flat")
    fig.colorbar(pc, ax=ax, label="max strain over the run (stable cells)")
    for r in grid:
        if r["stable"] != "1":
            ax.plot(num(r["dt_factor"]), num(r["k_over_m_per_s2"]), "x", color="red", ms=7, mew=1.5)
    ax.plot([], [], "x", color="red", label="blew up (NaN, > 50 m/s or energy growth)")
    ax.axvline(1.0, color="k", ls="--", label="paper's bound, eq. 4 (K = stiffest spring)")
    if edges:
        ek = [num(r["k_over_m_per_s2"]) for r in edges]
        ax.plot([num(r["measured_edge_factor"]) for r in edges], ek, "-", color="orange", lw=2.5,
                label="measured edge (bisection)")
        ax.plot([num(r["per_node_bound_factor"]) for r in edges], ek, "-", color="magenta", lw=1.5,
                label="eq. 4 with K per node (sum at a node)")
    auto = [r for r in cells if r["automatic"] == "1"]
    ax.scatter([num(r["dt_factor"]) for r in auto], [num(r["k_over_m_per_s2"]) for r in auto], marker="D",
               c=["white" if r["stable"] == "1" else "red" for r in auto], edgecolor="k", s=45, zorder=5,
               label="automatic dt (0.9 x per-node bound): white = stable")
    ax.set_yscale("log")
    ax.set_xlim(fedges[0], fedges[-1])
    ax.set_xlabel("dt / paper's bound 0.4 pi sqrt(m / K)")
    ax.set_ylabel("K / m (1/s^2)")
    ax.set_title("Explicit Euler cloth: stable and unstable cells")
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    image(save(fig, "stability_cloth.png"), "cloth stability map")
    if edges:
        report.append(table(["K/m 1/s^2", "paper's bound ms", "measured edge (x bound)", "per-node bound (x bound)",
                             "automatic dt (x bound)", "automatic dt stable"],
                            [[fmt(r["k_over_m_per_s2"]), ms(r["dt_paper_s"]), fmt(r["measured_edge_factor"]),
                              fmt(r["per_node_bound_factor"]), fmt(r["automatic_factor"]),
                              yes(next((c["stable"] for c in auto if c["k_over_m_per_s2"] == r["k_over_m_per_s2"]), "0"))]
                             for r in edges]))
        report.append("")
    unstable_below = [r for r in grid if r["stable"] != "1" and num(r["dt_factor"]) <= 1.0]
    report.append(f"Cells at or below the paper's bound that blew up: {len(unstable_below)} of "
                  f"{len([r for r in grid if num(r['dt_factor']) <= 1.0])}. Automatic dt: "
                  f"{sum(r['stable'] == '1' for r in auto)} of {len(auto)} stable.\n")

if zones:
    report.append("### The resolver's zone solves\n")
    report.append(
        "Constructed zones (clearance 1 mm): duplicate stencils, nearly parallel pairs, fans of ten in a cone, "
        "nearly equal face stencils, opposing stencils (infeasible), and a chain of 80 face stencils (solved by "
        "Hildreth's method above 64). 'condition' is lambda_max / lambda_min of Dx^T Dx from its eigenvalues "
        "(inf: singular); the solver adds 1e-10 max diag to the diagonal and refines. 'displacement ratio' is "
        "the largest vertex move over the largest move one stencil alone asks for.\n")
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    cases = []
    for r in zones:
        if r["case"] not in cases:
            cases.append(r["case"])
    style = {c: (plt.cm.tab10(i), "osD^vPX*"[i % 8], ["-", "--", "-.", ":"][i % 4]) for i, c in enumerate(cases)}
    big = 1e20
    for c in cases:
        if "duplicate" in c:
            continue  # its parameter is the number of copies, not an angle (singular for any count)
        rs = [r for r in zones if r["case"] == c]
        x = [num(r["parameter"]) for r in rs]
        y = [big if math.isinf(num(r["condition"])) else num(r["condition"]) for r in rs]
        col, mk, ls = style[c]
        axes[0].plot(x, y, ls, marker=mk, color=col, ms=5, mfc="none", label=c)
    axes[0].axhline(big, color="grey", ls=":", label="singular (plotted at 1e20)")
    axes[0].set_xscale("log")
    axes[0].set_yscale("log")
    axes[0].set_xlabel("angle (rad) or weight difference between the stencils")
    axes[0].set_ylabel("condition number of Dx^T Dx")
    axes[0].set_title("Conditioning of constructed zones")
    for c in cases:
        rs = [r for r in zones if r["case"] == c]
        x = [big if math.isinf(num(r["condition"])) else num(r["condition"]) for r in rs]
        y = [num(r["displacement_ratio"]) for r in rs]
        col, mk, ls = style[c]
        axes[1].scatter(x, y, s=30, color=col, marker=mk, facecolors="none", label=c)
    axes[1].set_xscale("log")
    axes[1].set_ylim(0, max(5, max(num(r["displacement_ratio"]) for r in zones) * 1.1))
    axes[1].set_xlabel("condition number of Dx^T Dx (1e20: singular)")
    axes[1].set_ylabel("max vertex move / largest single-stencil move")
    axes[1].set_title("Every solve finite, every move bounded")
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=style[c][0], marker=style[c][1], ls=style[c][2], mfc="none", label=c) for c in cases]
    handles.append(Line2D([], [], color="grey", ls=":", label="singular (condition plotted at 1e20)"))
    fig.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.35, 0.0), ncol=4, fontsize=7.5, frameon=False)
    if szones:
        srcs = []
        for r in szones:
            if r["scene"] not in srcs:
                srcs.append(r["scene"])
        fin = [num(r["condition"]) for r in szones if math.isfinite(num(r["condition"]))]
        if fin:
            bins = np.logspace(0, max(1.0, math.log10(max(fin)) + 0.5), 30)
            data = [[num(r["condition"]) for r in szones if r["scene"] == s and math.isfinite(num(r["condition"]))]
                    for s in srcs]
            labels = [f"{s} ({sum(1 for r in szones if r['scene'] == s and math.isinf(num(r['condition'])))} singular, not shown)"
                      for s in srcs]
            axes[2].hist(data, bins=bins, stacked=True, label=labels)
            axes[2].set_xscale("log")
            axes[2].set_yscale("symlog", linthresh=10)
        axes[2].set_xlabel("condition number of Dx^T Dx")
        axes[2].set_ylabel("zones (first 3 rounds of each section 1 scene)")
        axes[2].set_title("Zones the resolver meets")
        axes[2].legend(fontsize=6.5)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    fig.savefig(os.path.join(OUT, "stability_zones.png"))
    plt.close(fig)
    image("stability_zones.png", "zone conditioning")
    rows = []
    for r in zones:
        rows.append([r["case"], fmt(r["parameter"]), r["stencils"], fmt(r["condition"]), fmt(r["regularized_condition"]),
                     r["method"], yes(r["feasible"]), yes(r["finite"]), mm(r["max_violation_m"]),
                     mm(r["max_displacement_m"]), fmt(r["displacement_ratio"])])
    report.append(table(["case", "parameter", "stencils", "condition", "regularized", "method", "feasible", "finite",
                         "max violation mm", "max displacement mm", "displacement ratio"], rows))
    report.append("")
    if szones:
        fin = [num(r["condition"]) for r in szones if math.isfinite(num(r["condition"]))]
        sing = sum(1 for r in szones if math.isinf(num(r["condition"])))
        report.append(f"Zones met on the section 1 scenes: {len(szones)}; condition number median "
                      f"{fmt(np.median(fin)) if fin else '-'}, max {fmt(max(fin)) if fin else '-'}; singular "
                      f"(duplicate or dependent stencils): {sing}; infeasible: "
                      f"{sum(1 for r in szones if r['feasible'] != '1')}.\n")

# ------------------------------------------------------------------------------------------------
# 4. Extreme cases.
ext = read("extreme.csv")
if ext:
    report.append("## 4. Extreme cases\n")
    report.append(
        "Each case runs the resolver (defaults, time budget "
        f"{'10' if summary.get('mode') == 'quick' else '30'} s) in a forked child with a watchdog, so a crash or "
        "a hang would be reported here rather than stop the suite. Counts before and after are the "
        "independent referee's (inside only for closed bodies).\n")
    rows = []
    for r in ext:
        rows.append([f"`{r['case']}`", r["what"], r["status"], "**yes**" if r["converged"] == "1" else "no",
                     r["iterations"], ms(r["seconds"]),
                     f"{r['garment_edge_before']} / {r['body_edge_before']} / {r['inside_before']}",
                     f"{r['garment_edge_after']} / {r['body_edge_after']} / {r['inside_after']}",
                     r["reason"]])
    report.append(table(["case", "what", "run", "converged", "iterations", "ms",
                         "before: crossings g / b / inside", "after", "reason"], rows))
    report.append("")
    fig, ax = plt.subplots(figsize=(10, 0.32 * len(ext) + 1.5))
    y = np.arange(len(ext))
    before = [num(r["garment_edge_before"]) + num(r["body_edge_before"]) + num(r["inside_before"]) for r in ext]
    after = [num(r["garment_edge_after"]) + num(r["body_edge_after"]) + num(r["inside_after"]) for r in ext]
    ax.barh(y + 0.2, before, 0.4, color="lightgrey", label="before")
    ax.barh(y - 0.2, after, 0.4, color=["tab:green" if r["converged"] == "1" else "tab:orange" for r in ext],
            label="after (green: converged, orange: not converged, reported)")
    ax.set_yticks(y)
    ax.set_yticklabels([r["case"] for r in ext], fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("symlog", linthresh=1)
    ax.set_xlabel("crossings (both directions) + vertices inside, independent count")
    ax.set_title("Extreme cases: error before and after the resolver")
    ax.legend(fontsize=7, loc="lower right")
    image(save(fig, "extreme_cases.png"), "extreme cases")

# ------------------------------------------------------------------------------------------------
# 5. Leaving out what a scene does not need.
calls = read("lean_calls.csv")
few = read("lean_few.csv")
if calls or few:
    report.append("## 5. Leaving out what a scene does not need\n")
if calls:
    report.append("First and second call on one body (each the fastest over fresh bodies): what the first call builds "
                  "(the body's BVH, its depth maps) the second reuses.\n")
    report.append(table(["what", "first call ms", "second call ms", "built by the first call ms", "builds after both calls"],
                        [[r["what"], ms(r["first_call_s"]), ms(r["second_call_s"]), ms(r["built_on_first_call_s"]),
                          r["builds_after_two_calls"]] for r in calls]))
    report.append("")
if few:
    report.append(
        "A clean garment (the wrinkled tube after resolving), then k of its vertices, spread over it, moved "
        "5 mm behind their nearest body face; the time per call against k, split by the resolver's own trace into "
        "the first pass (detection over the whole garment and the inside test: what a history-free method "
        "must pay once per frame, growing with the garment) and the rest (stencils, zone solves, re-detection "
        "round the moved faces, the inside status of the moved vertices: what should grow with k and not "
        "with the mesh sizes). Times are the fastest of the runs, the least disturbed by other load on the "
        "machine. A call on a clean garment does the first pass and stops: zero iterations.\n")
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.6))
    groups = []
    for r in few:
        g = (r["garment_vertices"], r["body_faces"])
        if g not in groups:
            groups.append(g)
    for g in groups:
        rs = [r for r in few if (r["garment_vertices"], r["body_faces"]) == g]
        x = [num(r["penetrating_vertices"]) for r in rs]
        lab = f"{g[0]} garment vertices, {g[1]} body faces"
        line, = a.plot(x, [1e3 * num(r["time_min_s"]) for r in rs], "-o", label=lab)
        a.plot(x, [1e3 * num(r["first_pass_min_s"]) for r in rs], ":", color=line.get_color())
        b.plot(x[1:], [1e3 * num(r["after_first_pass_min_s"]) for r in rs[1:]], "-o", color=line.get_color(), label=lab)
    a.plot([], [], ":", color="grey", label="of which the first pass (detection over the whole garment, inside test)")
    kmax = max(num(r["penetrating_vertices"]) for r in few)
    ref = [1e3 * num(r["after_first_pass_min_s"]) for r in few if num(r["penetrating_vertices"]) == 1]
    if ref:
        xs = np.array([1, kmax])
        b.plot(xs, np.median(ref) * xs, "k--", lw=1, label="proportional to k (through the median at k = 1)")
    a.set_xscale("symlog", linthresh=1)
    a.set_yscale("log")
    b.set_xscale("log")
    b.set_yscale("log")
    a.set_xlabel("penetrating vertices k (each 5 mm behind the body surface)")
    b.set_xlabel("penetrating vertices k")
    a.set_ylabel("time per call, fastest of the runs (ms)")
    b.set_ylabel("time after the first pass, fastest of the runs (ms)")
    a.set_title("Time per frame against penetrating vertices")
    b.set_title("The part that resolves the penetrations")
    a.legend(fontsize=7)
    b.legend(fontsize=7)
    image(save(fig, "lean_few.png"), "time against penetrating vertices")
    ks = sorted({int(num(r["penetrating_vertices"])) for r in few})
    rows = []
    for g in groups:
        rs = {int(num(r["penetrating_vertices"])): r for r in few if (r["garment_vertices"], r["body_faces"]) == g}
        rows.append([g[0], g[1], ms(next(iter(rs.values()))["detection_pass_s"])] +
                    [f"{ms(rs[k]['time_min_s'])} = {ms(rs[k]['first_pass_min_s'])} + {ms(rs[k]['after_first_pass_min_s'])}"
                     if k in rs else "-" for k in ks])
    report.append("Per call: total = first pass + the rest, ms (each the fastest of the runs; sums need not add up "
                  "exactly, the fastest total and the fastest parts may come from different runs).\n")
    report.append(table(["garment V", "body F", "bare detection pass ms"] + [f"k = {k}" for k in ks], rows))
    report.append("")
    for g in groups:
        rs = [r for r in few if (r["garment_vertices"], r["body_faces"]) == g and num(r["penetrating_vertices"]) >= 8]
        if rs:
            per_k = [1e3 * num(r["after_first_pass_min_s"]) / num(r["penetrating_vertices"]) for r in rs]
            report.append(f"- {g[0]} garment vertices, {g[1]} body faces: first pass {ms(min(num(r['first_pass_min_s']) for r in few if (r['garment_vertices'], r['body_faces']) == g))} ms; "
                          f"after it {fmt(min(per_k))}-{fmt(max(per_k))} ms per penetrating vertex (k >= 8).")
    report.append("")
    bad = [r for r in few if num(r["crossings_after_independent"]) + num(r["inside_after_independent"]) > 0]
    report.append(f"Independent count after every call: {'clean' if not bad else str(len(bad)) + ' calls left errors'}.\n")

with open(os.path.join(OUT, "report.md"), "w") as f:
    f.write("\n".join(report) + "\n")
print(os.path.join(OUT, "report.md"))
