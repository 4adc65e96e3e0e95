#!/usr/bin/python3
"""Summarises a whole-pipeline benchmark folder written by the bench_player nodelet
(launch/bench_pipeline.launch): writes summary.md (a table, with the issue's targets beside the
figures, and each stage's latency against the people in view) and bench_pipeline.png (resident memory and latency against the frame number), each
under a temporary name then renamed, and prints summary.md.

usage: bench_pipeline_report.py OUTPUT_DIR

Exits 1 with one line on stderr when the folder has no complete summary.json."""
import bisect
import csv
import itertools
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TARGET_FPS = 30.0
TARGET_CORES = 1.0
TARGET_P95_MS = 50.0


def fmt(v, spec=".1f"):
    return "-" if v is None else format(v, spec)


def table(s):
    lat, lab = s["latency_ms"] or {}, s["label_latency_ms"] or {}
    rss = s["rss_mb"]
    pacing = "max (closed loop, %d in flight)" % s["in_flight"] if s["mode"] == "max" else "rate %g Hz" % s["rate_hz"]
    rows = [
        ("input", "%d frames %dx%d from %d bag(s), looped; %.0f MB of images in memory" % (
            s["bag_frames"], s["width"], s["height"], len(s["bags"]), s["bag_images_mb"])),
        ("pacing", pacing),
        ("frames requested / published / processed / dropped", "%d / %d / %d / %d" % (
            s["frames_requested"], s["frames_published"], s["frames_processed"], s["frames_dropped"])),
        ("frames with a tracked person", "%d (%.2f tracks per frame)" % (s["frames_with_person"], s["tracks_per_frame"])),
        ("frames per second", fmt(s["fps"])),
        ("CPU, manager process (cores)", "%s (of which the player: %s)" % (fmt(s["cpu_cores"], ".2f"),
                                                                          fmt(s["player_cpu_cores"], ".3f"))),
        ("latency stamp -> states (ms): median / p95 / max", "%s / %s / %s" % (
            fmt(lat.get("median")), fmt(lat.get("p95")), fmt(lat.get("max")))),
        ("latency stamp -> label (ms): count, median / p95", "%d, %s / %s" % (
            s["labels"], fmt(lab.get("median")), fmt(lab.get("p95")))),
        ("copying a frame (ms, median)", fmt((s["copy_ms"] or {}).get("median"), ".2f")),
        ("RSS (MB): first / last / max", "%s / %s / %s" % (fmt(rss["first"], ".0f"), fmt(rss["last"], ".0f"),
                                                            fmt(rss["max"], ".0f"))),
        ("RSS growth, 2nd -> last quarter (MB per 1000 frames)", fmt(s["rss_growth_mb_per_1000_frames"], ".2f")),
        ("malformed messages mixed in (one after every N-th frame)",
         "%d (N = %d)" % (s.get("bad_messages", 0), s.get("bad_every", 0)) if s.get("bad_every") else "none"),
        ("wall time (s)", fmt(s["wall_s"])),
        ("load average at start / end", "%s / %s" % (s["load_average_start"], s["load_average_end"])),
    ]
    out = ["| measure | value |", "|---|---|"] + ["| %s | %s |" % r for r in rows]
    p95 = lat.get("p95")
    if s["mode"] == "max":
        keeps_up = "%s fps %s %g" % (fmt(s["fps"]), ">=" if s["fps"] >= TARGET_FPS else "<", TARGET_FPS)
    else:
        keeps_up = "%d of %d frames at %g Hz reached states" % (s["frames_processed"], s["frames_published"], s["rate_hz"])
    out += ["", "Targets (issue 6; figures, not a test):", "",
            "| target | measured | met |", "|---|---|---|",
            "| keeps up with 30 fps | %s | %s |" % (keeps_up, "yes" if (
                s["fps"] >= TARGET_FPS if s["mode"] == "max" else
                s["frames_dropped"] == 0 and s["rate_hz"] >= TARGET_FPS) else "no"),
            "| at most one core | %s cores | %s |" % (fmt(s["cpu_cores"], ".2f"),
                                                     "yes" if s["cpu_cores"] <= TARGET_CORES else "no"),
            "| p95 latency <= 50 ms | %s ms | %s |" % (fmt(p95), "yes" if p95 is not None and p95 <= TARGET_P95_MS
                                                        else "no")]
    if not s["complete"]:
        out.insert(0, "**Incomplete run: %s**\n" % (s["error"] or "interrupted"))
    return "\n".join(out) + "\n"


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def stage_table(folder):
    """Per stage (stages.csv: its latency once a second, from /diagnostics), the mean latency and a
    least-squares line against the mean number of tracks of the frames that arrived in that second:
    what a stage costs per person in view is the growth of its slope over the stage before it."""
    path = os.path.join(folder, "stages.csv")
    if not os.path.exists(path):
        return ""
    arrived = sorted((float(r["arrived_s"]), int(r["tracks"]))
                     for r in read_csv(os.path.join(folder, "frames.csv")) if r["tracks"])
    times = [t for t, _ in arrived]
    summed = list(itertools.accumulate((k for _, k in arrived), initial=0))  # tracks of the first i frames
    per_stage = {}
    for r in read_csv(path):
        at = float(r["at_s"])
        lo, hi = bisect.bisect_right(times, at - 1.0), bisect.bisect_right(times, at)  # frames in (at - 1, at]
        if hi - lo >= 10:  # a second with frames in it (not the start or the end)
            per_stage.setdefault(r["stage"], []).append(((summed[hi] - summed[lo]) / (hi - lo), float(r["latency_ms"])))
    rows = []
    for stage, pts in per_stage.items():
        n = len(pts)
        mx, my = sum(x for x, _ in pts) / n, sum(y for _, y in pts) / n
        sxx = sum((x - mx) ** 2 for x, _ in pts)
        slope = sum((x - mx) * (y - my) for x, y in pts) / sxx if n >= 5 and sxx > 0.05 * n else None
        rows.append((my, stage, n, mx, slope, None if slope is None else my + slope * (1.0 - mx)))
    if not rows:
        return ""
    rows.sort()
    out = ["", "Per stage, from /diagnostics (latency = the stage's output time minus the frame's stamp, 1 s means; "
           "the line is fitted over the seconds against the tracks in view):", "",
           "| stage | seconds | mean tracks | mean latency (ms) | at 1 track (ms) | + per extra track (ms) |",
           "|---|---|---|---|---|---|"]
    out += ["| %s | %d | %.2f | %.1f | %s | %s |" % (stage, n, mx, my, fmt(one), fmt(slope, ".2f"))
            for my, stage, n, mx, slope, one in rows]
    return "\n".join(out) + "\n"


def plot(folder):
    samples = read_csv(os.path.join(folder, "samples.csv"))
    frames = [r for r in read_csv(os.path.join(folder, "frames.csv")) if r["latency_ms"]]
    fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    a.plot([int(r["frame"]) for r in samples], [float(r["rss_mb"]) for r in samples], marker=".", lw=1)
    a.set_ylabel("manager RSS (MB)")
    a.grid(alpha=0.3)
    b.plot([int(r["frame"]) for r in frames], [float(r["latency_ms"]) for r in frames], ",", alpha=0.4,
           label="each frame")
    b.plot([int(r["frame"]) for r in samples[1:]], [float(r["latency_p95_ms"]) for r in samples[1:]], lw=1.2,
           label="p95 per %s frames" % (int(samples[1]["frame"]) if len(samples) > 1 else "?"))
    b.axhline(TARGET_P95_MS, color="red", lw=0.8, ls="--", label="target p95 50 ms")
    b.set_ylabel("latency stamp -> states (ms)")
    b.set_xlabel("frame")
    b.grid(alpha=0.3)
    b.legend(loc="upper right", fontsize=8)
    fig.suptitle("Whole pipeline through the nodelet manager")
    path = os.path.join(folder, "bench_pipeline.png")
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=100, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bench_pipeline_report.py OUTPUT_DIR")
    folder = sys.argv[1]
    path = os.path.join(folder, "summary.json")
    try:
        with open(path) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"bench_pipeline_report: cannot read '{path}': {e}")
    md = table(s) + stage_table(folder)
    tmp = os.path.join(folder, "summary.md.tmp")
    with open(tmp, "w") as f:
        f.write(md)
    os.replace(tmp, os.path.join(folder, "summary.md"))
    plot(folder)
    print(md, end="")
    print(f"(written: {folder}/summary.md, summary.json, samples.csv, frames.csv, labels.csv, stages.csv, "
          "bench_pipeline.png)")


if __name__ == "__main__":
    main()
