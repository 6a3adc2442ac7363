#!/usr/bin/python3
"""The moving-body tables of README (Results, A moving body), measured again on this machine.

Runs `tryon animate resolve` on the walk's four garments and `tryon animate drape` with the
shipped hm08 patterns and GarmentCode's shirt, and prints both tables in README's columns:
the referee's counts and the shape from runs with --check, the milliseconds from runs without it
(the referee's count between frames evicts the caches). Each timed variant runs --repeat times
(default 5), alternated with the other variants (warm, cold and full relaxation; ahead and
--sequential); a table gives the run whose mean is the median of those runs' means, and the
smallest and largest of them (a 2-core virtual machine has slow spells: the same build's mean
moves by up to 1.4 times from one minute to the next). The jitter columns
are measured here from the PC2 files written (each vertex's correction, output minus input, from
one frame to the next), not taken from the tool's own report.

Usage: scripts/walk_benchmark.py [--data DIR] [--out DIR] [--only resolve|drape] [--garments A,B]
                                 [--motion walk|reversed|double] [--repeat N]
  --data   the shared data (default ../shared/data next to the repository; the walk is in
           DIR/animation, GarmentCode's shirt in DIR/garmentcode)
  --out    where the runs' JSON lines and PC2 files go (default ./walk_benchmark)
  --only   one of the two tables
  --garments  resolve: cache names (e.g. skirt_female_elegantsuit01); drape: pattern names
           (dress, dress_paper_size: the dress at the paper's 3,840 vertices, ..., garmentcode_shirt)
  --motion another motion made from the walk, its caches written into --out: `reversed`, the
           walk played backwards; `double`, every second frame at the same frame rate (the walk
           at twice its speed: the skin up to 7.4 m/s instead of 3.7). Default: the walk.
  --repeat how many times each timed variant runs (default 5; odd, so that one run is the median)
The tool is taken from $VT_WS/devel/lib/virtual_tryon/tryon (VT_WS default: .ws in the
repository); build it first (scripts/build.sh). Takes about 10 minutes for the resolve table and
22 for the drape table on a 2-core machine (the referee's brute-force counts dominate).
"""
import argparse
import json
import os
import statistics
import struct
import subprocess
import sys

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESOLVE_GARMENTS = ["skirt_female_elegantsuit01", "tshirt_male_casualsuit04", "trousers_jeans_female_casualsuit01",
                    "tshirt_female_casualsuit01_top"]
RESOLVE_NAMES = {"skirt_female_elegantsuit01": "skirt", "tshirt_male_casualsuit04": "male T-shirt",
                 "trousers_jeans_female_casualsuit01": "jeans", "tshirt_female_casualsuit01_top": "female T-shirt"}
DRAPE_PATTERNS = ["dress", "dress_paper_size", "skirt", "sleeveless_shirt", "tshirt", "garmentcode_shirt", "trousers"]
# The moving-body issue's dress has the paper's 3,840 vertices (Vassilev et al., Table 2): the
# shipped dress meshed at 0.0168 m instead of the default 0.02 has 3,912.
PAPER_SIZE_SPACING = "0.0168"


def tryon_binary():
    ws = os.environ.get("VT_WS", os.path.join(REPO, ".ws"))
    path = os.path.join(ws, "devel", "lib", "virtual_tryon", "tryon")
    if not os.access(path, os.X_OK):
        sys.exit("walk_benchmark: %s not found: build first (scripts/build.sh)" % path)
    return path


def run(args):
    """Runs tryon with args; returns its JSON lines (frames, then the summary)."""
    done = subprocess.run([tryon_binary()] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode not in (0, 3):
        sys.exit("walk_benchmark: tryon %s failed (%d): %s" % (" ".join(args), done.returncode, done.stderr.strip()))
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]


def read_pc2(path):
    """A Point Cache 2 file as an array of frames x points x 3."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:12] != b"POINTCACHE2\0":
        sys.exit("walk_benchmark: %s is not a Point Cache 2 file" % path)
    points, = struct.unpack_from("<i", data, 16)
    samples, = struct.unpack_from("<i", data, 28)
    return np.frombuffer(data, dtype="<f4", count=samples * points * 3, offset=32).reshape(samples, points, 3)


def write_pc2(path, frames, like):
    """frames (samples x points x 3) as a Point Cache 2 file with the start and rate of `like`."""
    with open(like, "rb") as f:
        header = f.read(32)
    start, rate = struct.unpack_from("<ff", header, 20)
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, frames.shape[1], start, rate, frames.shape[0]))
        f.write(np.ascontiguousarray(frames, dtype="<f4").tobytes())


def motion_cache(path, out, motion):
    """The cache at `path` for `motion`: itself for the walk, else the derived one written into out."""
    if motion == "walk":
        return path
    frames = read_pc2(path)
    frames = frames[::-1] if motion == "reversed" else frames[::2]
    derived = os.path.join(out, "%s_%s" % (motion, os.path.basename(path)))
    write_pc2(derived, frames, path)
    return derived


def jitter(output_pc2, input_pc2):
    """Per frame after the first, the largest change of a vertex's correction (mm)."""
    correction = read_pc2(output_pc2).astype(np.float64) - read_pc2(input_pc2).astype(np.float64)
    return [1e3 * float(np.linalg.norm(correction[f] - correction[f - 1], axis=1).max())
            for f in range(1, correction.shape[0])]


def frames_of(lines):
    return [d for d in lines if "frame" in d]


def summary_of(lines):
    return lines[-1]["summary"]


def max_median(values):
    return "%.1f / %.1f" % (max(values), statistics.median(values))


def median_run(runs):
    """Of several runs of one variant, the one whose mean ms a frame is the median of theirs."""
    ordered = sorted(runs, key=lambda lines: summary_of(lines)["ms_mean"])
    return ordered[(len(ordered) - 1) // 2]


def spread(runs):
    """The smallest and largest mean ms a frame over several runs of one variant."""
    means = [summary_of(lines)["ms_mean"] for lines in runs]
    return "%.1f-%.1f" % (min(means), max(means))


def resolve_runs(data, out, garment, motion, body_cache, repeat):
    anim = os.path.join(data, "animation")
    cache = motion_cache(os.path.join(anim, garment + "_walk.pc2"), out, motion)
    base = ["animate", "resolve", "--body", os.path.join(anim, "body_hm08.obj"), "--body-cache", body_cache,
            "--garment", os.path.join(anim, garment + ".obj"), "--garment-cache", cache]
    r = {"input": cache}

    def save(name, lines):
        with open(os.path.join(out, "resolve_%s_%s.jsonl" % (garment, name)), "w") as f:
            f.write("\n".join(json.dumps(d) for d in lines) + "\n")

    def variant(name, extra):
        path = os.path.join(out, "resolve_%s_%s" % (garment, name))
        r[name] = run(base + ["--out", path + ".pc2"] + extra)
        r[name + "_pc2"] = path + ".pc2"
        save(name, r[name])

    variant("warm_check", ["--check"])
    variant("cold_check", ["--check", "--cold"])
    variant("warm_forward", ["--no-backward"])
    variant("warm_none", ["--max-jitter", "0"])
    variant("cold_forward", ["--cold", "--no-backward"])
    variant("cold_none", ["--cold", "--max-jitter", "0"])
    for _ in range(repeat):  # alternated, so that a slow spell falls on every variant alike
        for name, extra in (("warm_time", []), ("cold_time", ["--cold"]), ("full_time", ["--full-relaxation"])):
            variant(name, extra)
            r.setdefault(name + "_runs", []).append(r[name])
    for name in ("warm_time", "cold_time", "full_time"):
        r[name] = median_run(r[name + "_runs"])
        save(name, r[name])  # the lines of the run the tables give, not of the last one
    return r


def strain_columns(frames):
    """The largest edge strain against each frame's own input (after the coherence step), the
    largest 99th percentile over the frames, and how many frames are over 0.3."""
    over = sum(1 for d in frames if d["strain_vs_input_max"] > 0.3)
    return "%.3f / %.3f" % (max(d["strain_vs_input_max"] for d in frames), max(d["p99_edge_strain"] for d in frames)), over


def timing_columns(lines):
    """ms mean / median / max over every frame (the summary's), and the body's and the resolver's
    means over the frames after the first (frame 0 builds the body's trees)."""
    s, frames = summary_of(lines), [d for d in frames_of(lines) if d["frame"] > 0]
    body = statistics.mean(d["ms_body"] for d in frames)
    resolve = statistics.mean(d["ms_resolve"] for d in frames)
    return "%.1f / %.1f / %.1f" % (s["ms_mean"], s["ms_median"], s["ms_max"]), "%.1f" % body, "%.1f" % resolve


def jitter_column(r, mode):
    return "%s (%s; %s)" % (max_median(jitter(r[mode + "_check_pc2"], r["input"])),
                            max_median(jitter(r[mode + "_forward_pc2"], r["input"])),
                            max_median(jitter(r[mode + "_none_pc2"], r["input"])))


def resolve_tables(data, out, garments, motion, repeat):
    warm_rows, cold_rows, relax_rows = [], [], []
    body_cache = motion_cache(os.path.join(data, "animation", "body_hm08_walk.pc2"), out, motion)
    for g in garments:
        print("walk_benchmark: resolve %s" % g, file=sys.stderr)
        r = resolve_runs(data, out, g, motion, body_cache, repeat)
        relax_rows.append([RESOLVE_NAMES.get(g, g)] + relaxation_columns(r["warm_time"]) +
                          relaxation_columns(r["full_time"]))
        for mode, rows in (("warm", warm_rows), ("cold", cold_rows)):
            check = frames_of(r[mode + "_check"])
            s = summary_of(r[mode + "_check"])
            strain, over = strain_columns(check)
            ms, body, resolve = timing_columns(r[mode + "_time"])
            left = "%d / %d / %d" % (s["vertices_over_max_jitter"], s["vertices_left_over_max_jitter"],
                                     s["backward_vertices_left_over"])
            findings = s.get("frames_with_referee_findings", "?")
            if mode == "warm":
                cold_frames = frames_of(r["cold_check"])
                crossings = [d["crossings_before"] for d in cold_frames]
                rows.append([RESOLVE_NAMES.get(g, g), str(len(check)), "%d-%d" % (min(crossings), max(crossings)), ms,
                             spread(r["warm_time_runs"]), body, resolve, strain, str(over), jitter_column(r, mode),
                             left, str(s["warm_frames_resolved_cold"]), str(findings)])
            else:
                rows.append([RESOLVE_NAMES.get(g, g), ms, spread(r["cold_time_runs"]), strain, str(over),
                             jitter_column(r, mode), left, str(findings)])
    runs = "means of the %d runs" % repeat
    print_table(["garment", "frames", "crossings in the input (per frame)", "ms mean / median / max", runs, "of which body",
                 "resolve", "strain max / p99 (worst frames)", "frames over 0.3",
                 "jitter max / median mm after the backward pass (forward pass alone; without coherence)",
                 "vertices over 3 mm / left over forward / left over after the backward pass",
                 "warm frames resolved cold", "frames with referee findings"], warm_rows)
    print()
    print("The same with `--cold`:")
    print()
    print_table(["garment", "ms mean / median / max", runs, "strain max / p99 (worst frames)", "frames over 0.3",
                 "jitter max / median mm after the backward pass (forward pass alone; without coherence)",
                 "vertices over 3 mm / left over forward / left over after the backward pass",
                 "frames with referee findings"], cold_rows)
    print()
    print("Warm frames relaxed locally (the default) and with `--full-relaxation`, the same runs:")
    print()
    print_table(["garment", "local: ms mean / median / max", "relaxed vertices a warm frame (mean)",
                 "widened frames", "strain max / p99", "full: ms mean / median / max",
                 "relaxed vertices a warm frame (mean)", "widened frames", "strain max / p99"], relax_rows)


def relaxation_columns(lines):
    """ms, the mean of relaxed vertices over the warm frames, the frames widened and the strain
    (the tool's own, against each frame's input) of one run."""
    s, frames = summary_of(lines), frames_of(lines)
    warm = [d for d in frames if d["warm_start"]]
    relaxed = statistics.mean(d["relaxed_vertices"] for d in warm) if warm else 0
    strain, _ = strain_columns(frames)
    return ["%.1f / %.1f / %.1f" % (s["ms_mean"], s["ms_median"], s["ms_max"]), "%.0f" % relaxed,
            str(s.get("relaxations_widened", 0)), strain]


def pattern_path(data, name):
    """The pattern file, the table's label and the options it is draped with."""
    if name == "garmentcode_shirt":
        return os.path.join(data, "garmentcode", "shirt_mean_specification.json"), "GarmentCode shirt", []
    if name == "dress_paper_size":
        return (os.path.join(REPO, "config", "patterns", "hm08", "dress.yaml"),
                "hm08 dress, the paper's size (spacing %s m)" % PAPER_SIZE_SPACING, ["--spacing", PAPER_SIZE_SPACING])
    return os.path.join(REPO, "config", "patterns", "hm08", name + ".yaml"), "hm08 " + name.replace("_", " "), []


def drape_tables(data, out, patterns, motion, repeat):
    anim = os.path.join(data, "animation")
    body_cache = motion_cache(os.path.join(anim, "body_hm08_walk.pc2"), out, motion)
    rows = []
    for name in patterns:
        print("walk_benchmark: drape %s" % name, file=sys.stderr)
        pattern, label, options = pattern_path(data, name)
        base = ["animate", "drape", "--body", os.path.join(anim, "body_hm08.obj"), "--body-cache", body_cache,
                "--pattern", pattern] + options
        prefix = os.path.join(out, "drape_" + name)
        check = run(base + ["--out", prefix + "_check", "--check"])
        with open(prefix + "_check.jsonl", "w") as f:
            f.write("\n".join(json.dumps(d) for d in check) + "\n")
        aheads, sequentials = [], []
        for _ in range(repeat):  # alternated, so that a slow spell falls on both alike
            aheads.append(run(base + ["--out", prefix + "_ahead"]))
            sequentials.append(run(base + ["--out", prefix + "_sequential", "--sequential"]))
        ahead, sequential = median_run(aheads), median_run(sequentials)
        frames, s = [d for d in frames_of(check) if d["frame"] > 0], summary_of(check)
        clean = sum(1 for d in frames if isinstance(d.get("referee"), dict) and not any(
            d["referee"].get(k, 0) for k in ("garment_edge_crossings", "body_edge_crossings", "vertices_inside")))
        over = sum(1 for d in frames if d["strain_max"] > 0.15)
        timed = [d for d in frames_of(ahead) if d["frame"] > 0]
        mean = lambda k: statistics.mean(d.get(k, 0) for d in timed)
        t = summary_of(ahead)
        vertices = frames_of(check)[0].get("drape", {}).get("vertices", "?")
        rows.append([label, str(vertices), str(len(frames)), str(clean),
                     "%.3f (%d)" % (s["strain_max"], over), str(sum(1 for d in frames if d.get("resolved_relaxed"))),
                     str(s["frames_carried_with_skin"]), str(s["frames_corrected_quickly"]),
                     "%.1f / %.1f / %.1f" % (t["ms_mean"], t["ms_median"], t["ms_max"]), spread(aheads),
                     "%.1f / %.1f; %.1f / %.1f" % (mean("ms_body"), mean("ms_maps"), mean("ms_cloth"), mean("ms_resolve")),
                     "%.1f" % summary_of(sequential)["ms_mean"], "%d" % round(mean("steps")), str(s["not_converged"])])
    print_table(["garment", "vertices", "frames stepped", "frames clean by the referee", "largest strain (frames over 0.15)",
                 "frames resolved again and kept", "frames carried with the skin", "frames corrected quickly",
                 "ms mean / median / max", "means of the %d runs" % repeat,
                 "made ahead: body / maps; on the cloth's thread: cloth / resolve",
                 "ms mean, one after the other (`--sequential`)", "steps a frame", "frames not converged"], rows)


def print_table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(row) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.path.join(os.path.dirname(REPO), "shared", "data"))
    parser.add_argument("--out", default="walk_benchmark")
    parser.add_argument("--only", choices=["resolve", "drape"])
    parser.add_argument("--garments")
    parser.add_argument("--motion", choices=["walk", "reversed", "double"], default="walk")
    parser.add_argument("--repeat", type=int, default=5)
    a = parser.parse_args()
    if a.repeat < 1 or a.repeat % 2 == 0:
        sys.exit("walk_benchmark: --repeat must be odd and at least 1")
    if not os.path.isfile(os.path.join(a.data, "animation", "body_hm08_walk.pc2")):
        sys.exit("walk_benchmark: no walk in %s/animation (give --data)" % a.data)
    os.makedirs(a.out, exist_ok=True)
    chosen = a.garments.split(",") if a.garments else None
    if a.only != "drape":
        resolve_tables(a.data, a.out, chosen or RESOLVE_GARMENTS, a.motion, a.repeat)
        print()
    if a.only != "resolve":
        drape_tables(a.data, a.out, chosen or DRAPE_PATTERNS, a.motion, a.repeat)


if __name__ == "__main__":
    main()
