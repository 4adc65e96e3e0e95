#!/usr/bin/env python3
"""Pictures of evaluate_tracking's results: for each scene, the people's lateral position on the
floor over time (truth, coloured by person; thin where they do not count) beside the tracker's
tracks (coloured by track id), and their distance from the camera below.

usage: plot_tracks.py RESULTS_DIR [SCENE ...]
Reads RESULTS_DIR/report.json and RESULTS_DIR/tracks/<scene>.csv; writes RESULTS_DIR/tracks/<scene>.png
(every scene of the report, or only those named).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    truth, tracks = {}, {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            kind = truth if row["kind"] == "truth" else tracks
            kind.setdefault(int(row["id"]), []).append(
                (float(row["stamp"]), float(row["x"]), float(row["y"]), row["counted"] == "1"))
    return truth, tracks


def runs(points, gap):
    """Splits a trajectory where time jumps by more than gap (so that gaps are not drawn as lines)."""
    out, cur = [], []
    for p in points:
        if cur and p[0] - cur[-1][0] > gap:
            out.append(cur)
            cur = []
        cur.append(p)
    if cur:
        out.append(cur)
    return out


def draw(ax_lat, ax_depth, trajectories, colour_of, counted_only, label_prefix):
    for ident, points in sorted(trajectories.items()):
        colour = colour_of(ident)
        for part in runs(points, 0.2):
            t = [p[0] for p in part]
            for ax, k in ((ax_lat, 2), (ax_depth, 1)):
                ax.plot(t, [p[k] for p in part], color=colour, lw=0.6 if counted_only else 1.8,
                        alpha=0.5 if counted_only else 1.0)
                if counted_only:
                    # Bold where the person counts (head seen, enough of them visible).
                    vals = [p[k] if p[3] else float("nan") for p in part]
                    ax.plot(t, vals, color=colour, lw=2.0)
        first = points[0]
        ax_lat.annotate("%s%d" % (label_prefix, ident), (first[0], first[2]), fontsize=7, color=colour)


def plot_scene(results, scene, summary):
    truth, tracks = read_rows(os.path.join(results, "tracks", scene + ".csv"))
    fig, axes = plt.subplots(2, 2, figsize=(13, 6.5), sharex=True, sharey="row")
    people = plt.get_cmap("Set1")
    ids = plt.get_cmap("tab20")
    draw(axes[0][0], axes[1][0], truth, lambda i: people((i - 1) % 9), True, "person ")
    draw(axes[0][1], axes[1][1], tracks, lambda i: ids(i % 20), False, "")
    axes[0][0].set_title("truth: people (bold where they count)")
    s = summary["scores"]
    axes[0][1].set_title("tracks (colour = track id): MOTA %.3f, IDF1 %.3f, %d id switches, %d tracks"
                         % (s["mota"], s["idf1"], s["id_switches"], s["predicted_ids"]))
    for col in (0, 1):
        axes[0][col].set_ylabel("lateral y on the floor (m, + = left)")
        axes[1][col].set_ylabel("distance x from the camera (m)")
        axes[1][col].set_xlabel("time (s)")
        axes[0][col].grid(alpha=0.3)
        axes[1][col].grid(alpha=0.3)
    fig.suptitle("%s (%s): %d people, %d crossings in the image" %
                 (scene, summary["actors"], summary["people"], summary["crossings"]))
    fig.tight_layout()
    out = os.path.join(results, "tracks", scene + ".png")
    fig.savefig(out + ".tmp.png", dpi=90)
    os.replace(out + ".tmp.png", out)
    plt.close(fig)
    return out


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) >= 2 else 2
    results = argv[1]
    try:
        with open(os.path.join(results, "report.json")) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        print("plot_tracks.py: %s: %s" % (results, e), file=sys.stderr)
        return 1
    wanted = set(argv[2:])
    for summary in report.get("scenes", []):
        if wanted and summary["scene"] not in wanted:
            continue
        print("plot_tracks.py: " + plot_scene(results, summary["scene"], summary))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
