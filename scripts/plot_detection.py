#!/usr/bin/env python3
"""Pictures of evaluate --protocol detection's report (detection.json), beside it:

  detection.png           precision and recall per scene type, camera height, camera pitch, action
                          and visible floor; false detections by what they lie on; misses by cause
  detection_examples.png  one frame of each scene type with the tracker's people boxed
                          (green: a person found, red: a false detection, orange: a person missed,
                          grey: a person too little seen to be required)

usage: plot_detection.py DIR/detection.json
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.patches as patches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def value(x):
    return float("nan") if x is None else float(x)


def bars(ax, tally, title, order=None):
    keys = order if order else sorted(tally)
    keys = [k for k in keys if k in tally]
    p = [value(tally[k]["precision"]) for k in keys]
    r = [value(tally[k]["recall"]) for k in keys]
    xs = range(len(keys))
    ax.bar([x - 0.2 for x in xs], [0 if math.isnan(v) else v for v in p], 0.4, label="precision", color="#3b7dd8")
    ax.bar([x + 0.2 for x in xs], [0 if math.isnan(v) else v for v in r], 0.4, label="recall", color="#e0a030")
    for x, k, pv, rv in zip(xs, keys, p, r):
        note = "no det." if math.isnan(pv) else ""
        if math.isnan(rv):
            note += ("\n" if note else "") + "nobody"
        if note:
            ax.text(x, 0.05, note, ha="center", fontsize=7)
        ax.text(x, 1.02, "%d fp" % tally[k]["false_positives"], ha="center", fontsize=7)
    ax.axhline(0.95, color="grey", lw=0.8, ls="--")
    ax.set_xticks(list(xs))
    ax.set_xticklabels(keys, rotation=30, ha="right", fontsize=8)
    ax.set_ylim(0, 1.12)
    ax.set_title(title, fontsize=10)


def counts(ax, table, title, colour):
    keys = sorted(table, key=lambda k: -table[k])
    ax.barh(keys[::-1], [table[k] for k in keys][::-1], color=colour)
    ax.set_title(title, fontsize=10)
    ax.tick_params(labelsize=8)
    if not keys:
        ax.text(0.5, 0.5, "none", ha="center", transform=ax.transAxes)


def summary(report):
    o = report["overall"]
    return ("people detection, %s: %d clutter scenes, %d frames, gate %.2f m: precision %.3f, "
            "recall %.3f (%d found, %d false, %d missed)" % (
                report["tracker"], len(report["scenes"]), o["frames"], report["gate"], value(o["precision"]), value(o["recall"]),
                o["true_positives"], o["false_positives"], o["misses"]))


def plot_summary(report, out):
    fig, axes = plt.subplots(2, 4, figsize=(17, 8))
    kinds = ["wall", "chair", "table", "shelf", "door", "border", "furniture"]
    bars(axes[0][0], report["by_kind"], "per scene type", kinds)
    bars(axes[0][1], report["by_camera_height"], "camera height (m)")
    bars(axes[0][2], report["by_pitch_up_deg"], "camera pitch (deg, + = up)")
    bars(axes[0][3], report["by_floor_visible"], "floor seen in the first frame")
    bars(axes[1][0], report["by_action"], "action performed")
    counts(axes[1][1], report["false_positives_on"], "false detections: on what", "#c84040")
    counts(axes[1][2], report["misses_by_cause"], "misses: cause", "#e08030")
    axes[1][3].axis("off")
    axes[0][0].legend(fontsize=8, loc="lower left")
    fig.suptitle(summary(report), fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    fig.savefig(out, dpi=90)
    plt.close(fig)


COLOURS = {"tp": "#20c020", "fp": "#ff2020", "missed": "#ff9000", "truth": None, "ignored": "#a0a0a0"}


def plot_examples(report, folder, out):
    examples = report["examples"]
    if not examples:
        return
    cols = min(4, len(examples))
    rows = (len(examples) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.8 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, ex in zip(axes.flat, examples):
        ax.imshow(mpimg.imread(os.path.join(folder, ex["image"])))
        for b in ex["boxes"]:
            colour = COLOURS.get(b["what"])
            if colour is None:
                continue
            u0, v0, u1, v1 = b["box"]
            ax.add_patch(patches.Rectangle((u0, v0), u1 - u0, v1 - v0, fill=False, lw=2, ec=colour))
            label = b["what"] + (" (%s)" % b["on"] if "on" in b else "")
            ax.text(u0, max(0, v0 - 4), label, color=colour, fontsize=7, va="bottom")
        ax.set_title("%s, frame %d" % (ex["scene"], ex["frame"]), fontsize=9)
    fig.suptitle("green: person found, red: false detection, orange: person missed, grey: not required",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(out, dpi=80)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    with open(path) as f:
        report = json.load(f)
    folder = os.path.dirname(os.path.abspath(path))
    for name, draw in (("detection.png", lambda o: plot_summary(report, o)),
                       ("detection_examples.png", lambda o: plot_examples(report, folder, o))):
        final = os.path.join(folder, name)
        tmp = final + ".tmp.png"
        draw(tmp)
        if os.path.exists(tmp):
            os.replace(tmp, final)
            print("wrote " + final)


if __name__ == "__main__":
    main()
