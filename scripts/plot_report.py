#!/usr/bin/python3
"""Draws the pictures of an evaluation report folder (written by `evaluate`).

confusion_<variant>.png for every variant, accuracy_vs_frames.png (the paper's Figure 8) when
the report has a frames sweep, cross_view.png (accuracy against the test view) for the cross-view
protocol, reliability.png (share right against confidence, for the default recognizer, the
paper's and the joint baseline), and ablation.md, a table of the variants (accuracy, mean
confidence, expected calibration error) beside the paper's numbers. Writes each file under a temporary name and renames it."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PAPER = {  # IAS-Lab Action Dataset, leave-one-person-out, 30 frames (Munaro et al. 2013, Fig. 7)
    "meanflow": 58.0,
    "sumflow_raw": 81.9,
    "sumflow": 85.2,
    "sumflow_pca": 87.4,
}


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def confusion(variant, out):
    c = variant["confusion"]
    labels, m = c["labels"], c["matrix"]
    n = len(labels)
    rows = [max(1, sum(r)) for r in m]
    norm = [[v / rows[i] for v in r] for i, r in enumerate(m)]
    fig, ax = plt.subplots(figsize=(1.2 + 0.55 * n, 1.0 + 0.5 * n))
    ax.imshow(norm, cmap="Blues", vmin=0, vmax=1)
    ax.set_xticks(range(n), labels, rotation=60, ha="right")
    ax.set_yticks(range(n), labels)
    for i in range(n):
        for j in range(n):
            if m[i][j]:
                ax.text(j, i, str(m[i][j]), ha="center", va="center", fontsize=7,
                        color="white" if norm[i][j] > 0.5 else "black")
    ax.set_xlabel("predicted")
    ax.set_ylabel("true")
    ax.set_title(f"{variant['title']}: accuracy {100 * variant['accuracy']:.1f}%")
    save(fig, os.path.join(out, f"confusion_{variant['variant']}.png"))


def sweep(report, out):
    s = report["frames_sweep"]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(s["frames"], [100 * a for a in s["sumflow"]], "o-", ms=3, label="SUMFLOW")
    ax.plot(s["frames"], [100 * a for a in s["sumflow_pca"]], "s-", ms=3, label="SUMFLOW with PCA")
    ax.set_xlabel("frames per sequence descriptor")
    ax.set_ylabel("mean accuracy (%)")
    ax.set_ylim(0, 100)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"Accuracy against frames per sequence ({report['protocol']})")
    save(fig, os.path.join(out, "accuracy_vs_frames.png"))


def cross_view(report, out):
    cv = report["cross_view"]
    titles = {v["variant"]: v["title"] for v in report["variants"]}
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, acc in cv["accuracy"].items():
        ax.plot(cv["views"], [100 * a for a in acc], "o-", ms=4, label=titles.get(name, name))
    ax.set_xticks(cv["views"])
    ax.set_xlabel("test view (degrees from facing the camera)")
    ax.set_ylabel("accuracy (%)")
    ax.set_ylim(0, 100)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    spread = cv.get("train_spread", 15)
    trained = "on every side" if spread >= 180 else f"facing the camera (0 +- {spread:g} degrees)"
    ax.set_title(f"Trained {trained}, grid {cv.get('grid', 'camera-aligned')}; tested from each side", fontsize=10)
    save(fig, os.path.join(out, "cross_view.png"))


RELIABILITY_VARIANTS = ("posture_flow", "sumflow_pca", "joints")


def reliability(report, out):
    shown = [v for v in report["variants"]
             if v["variant"] in RELIABILITY_VARIANTS and v["confusion"].get("reliability", {}).get("answers")]
    if not shown:
        return
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot([0, 1], [0, 1], "k:", lw=1, label="calibrated")
    for v in shown:
        r = v["confusion"]["reliability"]
        pts = [(b["confidence"], b["correct"] / b["count"]) for b in r["bins"] if b["count"]]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=4,
                label=f"{v['title']} (ECE {r['expected_calibration_error']:.2f})")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xlabel("confidence of the label given (bin mean)")
    ax.set_ylabel("share of those labels that were right")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title(f"Reliability of the confidence ({report['protocol']})")
    save(fig, os.path.join(out, "reliability.png"))


def table(report, out):
    lines = ["| variant | accuracy (ours) | mean confidence | calibration error (ECE) | paper (IAS-Lab) |",
             "|---|---|---|---|---|"]
    for v in report["variants"]:
        paper = PAPER.get(v["variant"])
        r = v["confusion"].get("reliability", {})
        conf = f"{r['mean_confidence']:.2f}" if r.get("answers") else ""
        ece = f"{r['expected_calibration_error']:.2f}" if r.get("answers") else ""
        lines.append(f"| {v['title']} | {100 * v['accuracy']:.1f}% | {conf} | {ece} | "
                     f"{'' if paper is None else f'{paper}%'} |")
    tmp = os.path.join(out, "ablation.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, os.path.join(out, "ablation.md"))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_report.py REPORT_DIR")
    out = sys.argv[1]
    path = os.path.join(out, "report.json")
    try:
        with open(path) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"plot_report: {path}: {e}")
    for v in report["variants"]:
        confusion(v, out)
    if "frames_sweep" in report:
        sweep(report, out)
    if "cross_view" in report:
        cross_view(report, out)
    reliability(report, out)
    table(report, out)


if __name__ == "__main__":
    main()
