#!/usr/bin/env python3
"""Pictures of evaluate --protocol crowd's report (crowd.json), beside it:

  crowd.png   per recognizer variant: accuracy per person and per action, each person's actions
              recognised with them alone in view (light) and with everyone in view (dark), and the
              confusion matrix with everyone in view

usage: plot_crowd.py DIR/crowd.json
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def paired(ax, rows, names, title):
    xs = range(len(rows))
    ax.bar([x - 0.2 for x in xs], [r["alone"] for r in rows], 0.4, label="alone", color="#9cc3ee")
    ax.bar([x + 0.2 for x in xs], [r["together"] for r in rows], 0.4, label="everyone in view", color="#1f5fa8")
    for x, r in zip(xs, rows):
        ax.text(x, 1.02, str(r["segments"]), ha="center", fontsize=6)
    ax.set_xticks(list(xs))
    ax.set_xticklabels(names, rotation=45, ha="right", fontsize=7)
    ax.set_ylim(0, 1.1)
    ax.set_ylabel("accuracy")
    ax.set_title(title, fontsize=9)


def confusion(ax, c, title):
    labels, counts = c["labels"], c["matrix"]
    shares = [[n / max(1, sum(row)) for n in row] for row in counts]
    ax.imshow(shares, cmap="Blues", vmin=0, vmax=1)
    ax.set_xticks(range(len(labels)))
    ax.set_yticks(range(len(labels)))
    ax.set_xticklabels(labels, rotation=90, fontsize=6)
    ax.set_yticklabels(labels, fontsize=6)
    ax.set_xlabel("recognised", fontsize=7)
    ax.set_ylabel("performed", fontsize=7)
    ax.set_title(title, fontsize=9)


def plot(report, out):
    variants = report["variants"]
    fig, axes = plt.subplots(len(variants), 3, figsize=(19, 5 * len(variants)), squeeze=False,
                             gridspec_kw={"width_ratios": [2, 2, 1.2]})
    for row, v in zip(axes, variants):
        people = v["per_person"]
        paired(row[0], people, [p["person"] for p in people],
               "%s: per person (numbers: actions scored)" % v["title"])
        actions = sorted(v["per_action"])
        paired(row[1], [v["per_action"][a] for a in actions], actions, "per action")
        confusion(row[2], v["together_confusion"], "everyone in view")
        row[0].legend(fontsize=7, loc="lower left")
    first = variants[0] if variants else None
    head = "recognition of several people: %d crowd scenes of new people" % len(report["scenes"])
    if first:
        head += "; " + ", ".join("%s alone %.1f%%, together %.1f%%" % (v["variant"], 100 * v["alone"], 100 * v["together"])
                                 for v in variants)
    fig.suptitle(head, fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(out, dpi=80)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    with open(path) as f:
        report = json.load(f)
    final = os.path.join(os.path.dirname(os.path.abspath(path)), "crowd.png")
    tmp = final + ".tmp.png"
    plot(report, tmp)
    os.replace(tmp, final)
    print("wrote " + final)


if __name__ == "__main__":
    main()
