#!/usr/bin/python3
"""Draws the timeline of online recognition on continuous streams.

Usage: plot_timeline.py CSV OUTDIR

CSV has the header stream,kind,label,start,end,published (kind is truth or predicted; published
is empty for truth; times in seconds). Writes timeline_<stream>.png into OUTDIR for each stream:
the true actions in the upper lane, the recognised ones in the lower lane (overlapping
predictions stacked), one colour per label across all streams, and a tick at each prediction's
publish time. Time runs from the stream's first segment. Writes each file under a temporary name
and renames it."""
import csv
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["stream", "kind", "label", "start", "end", "published"]


def fail(msg):
    sys.exit(f"plot_timeline: {msg}")


def number(text, where, column):
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v):
        fail(f"{where}: column '{column}' must be a finite number, got '{text}'")
    return v


def read(path):
    """{stream: {"truth": [...], "predicted": [...]}} in file order; each segment a dict."""
    try:
        f = open(path, newline="")
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    streams = {}
    with f:
        reader = csv.reader(f)
        lines = []  # (line where the record ends, its fields) of the non-blank records
        try:
            for r in reader:
                if any(c.strip() for c in r):
                    lines.append((reader.line_num, [c.strip() for c in r]))
        except (csv.Error, UnicodeDecodeError) as e:
            fail(f"{path}:{reader.line_num + 1}: not a readable CSV ({e})")
    if not lines:
        fail(f"{path}: empty file (no header line)")
    n, header = lines[0]
    for c in COLUMNS:
        if c not in header:
            fail(f"{path}:{n}: header lacks column '{c}' (expected {','.join(COLUMNS)})")
    col = {c: header.index(c) for c in COLUMNS}
    for n, r in lines[1:]:
        where = f"{path}:{n}"
        if len(r) != len(header):
            fail(f"{where}: expected {len(header)} fields, found {len(r)}")
        g = {c: r[i] for c, i in col.items()}
        if not g["stream"]:
            fail(f"{where}: column 'stream' is empty")
        if g["kind"] not in ("truth", "predicted"):
            fail(f"{where}: column 'kind' must be truth or predicted, got '{g['kind']}'")
        if not g["label"]:
            fail(f"{where}: column 'label' is empty")
        seg = {"label": g["label"], "start": number(g["start"], where, "start"),
               "end": number(g["end"], where, "end")}
        if seg["end"] < seg["start"]:
            fail(f"{where}: end {g['end']} before start {g['start']}")
        if g["kind"] == "predicted":
            seg["published"] = number(g["published"], where, "published")
        elif g["published"]:
            fail(f"{where}: a truth segment has a publish time ('{g['published']}'); leave it empty")
        streams.setdefault(g["stream"], {"truth": [], "predicted": []})[g["kind"]].append(seg)
    if not streams:
        fail(f"{path}: no segments after the header")
    return streams


def colours(streams):
    labels = sorted({s["label"] for st in streams.values() for k in st.values() for s in k})
    cmap = plt.get_cmap("tab10" if len(labels) <= 10 else "tab20")
    return {lab: cmap(i % cmap.N) for i, lab in enumerate(labels)}


def rows_of(segments):
    """Stacks overlapping segments: the row of each, and how many rows there are."""
    ends, rows = [], []
    for s in segments:
        for i, e in enumerate(ends):
            if e <= s["start"]:
                ends[i] = s["end"]
                rows.append(i)
                break
        else:
            ends.append(s["end"])
            rows.append(len(ends) - 1)
    return rows, max(1, len(ends))


def lane(ax, segments, y0, height, colour, t0, ticks):
    rows, n = rows_of(sorted(segments, key=lambda s: (s["start"], s["end"])))
    h = height / n
    for s, r in zip(sorted(segments, key=lambda s: (s["start"], s["end"])), rows):
        y = y0 + height - (r + 1) * h
        x, w = s["start"] - t0, s["end"] - s["start"]
        ax.broken_barh([(x, w)], (y + 0.06 * h, 0.88 * h), facecolors=colour[s["label"]],
                       edgecolors="black", linewidth=0.5)
        ax.text(x + w / 2, y + h / 2, s["label"], ha="center", va="center", fontsize=7 if n == 1 else 6,
                clip_on=True)
        if ticks:
            p = s["published"] - t0
            ax.plot([p, p], [y + 0.06 * h - 0.12, y + 0.06 * h], color="black", linewidth=1.2,
                    solid_capstyle="butt")


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def plot(name, stream, colour, out):
    segs = stream["truth"] + stream["predicted"]
    t0 = min(s["start"] for s in segs)
    t1 = max([s["end"] for s in segs] + [s["published"] for s in stream["predicted"]])
    span = max(t1 - t0, 1e-3)
    fig, ax = plt.subplots(figsize=(min(24.0, max(6.0, 0.12 * span + 3.0)), 2.6))
    lane(ax, stream["truth"], 1.3, 1.0, colour, t0, ticks=False)
    lane(ax, stream["predicted"], 0.15, 1.0, colour, t0, ticks=True)
    ax.set_ylim(-0.05, 2.4)
    ax.set_xlim(-0.01 * span, span * 1.01)
    ax.set_yticks([0.65, 1.8], ["recognised", "truth"])
    ax.set_xlabel(f"time (s) from {t0:g}")
    ax.grid(axis="x", alpha=0.3)
    ax.set_title(f"{name}: {len(stream['truth'])} true actions, {len(stream['predicted'])} recognised "
                 "(ticks: publish times)", fontsize=9)
    save(fig, os.path.join(out, f"timeline_{re.sub(r'[^A-Za-z0-9._-]', '_', name)}.png"))


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_timeline.py CSV OUTDIR")
    path, out = sys.argv[1], sys.argv[2]
    streams = read(path)
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        fail(f"{out}: {e.strerror}")
    colour = colours(streams)
    for name, stream in streams.items():
        plot(name, stream, colour, out)


if __name__ == "__main__":
    main()
