#!/usr/bin/python3
"""Checks an evaluation report folder against the keys documented in docs/evaluation.md.

Exits 1 with one line per problem; prints "report OK" otherwise."""
import json
import os
import sys

NUMBER = (int, float)


def check(report, out):
    problems = []

    def need(obj, key, kind, where):
        if not isinstance(obj, dict) or key not in obj:
            problems.append(f"{where}: missing key '{key}'")
            return None
        if not isinstance(obj[key], kind):
            problems.append(f"{where}.{key}: expected {kind}, got {type(obj[key]).__name__}")
            return None
        return obj[key]

    need(report, "protocol", str, "report")
    need(report, "folds", int, "report")
    need(report, "frames", int, "report")
    samples = need(report, "samples", dict, "report")
    for k in ("total", "people", "without_flow", "train_per_fold", "test_per_fold"):
        need(samples or {}, k, int, "samples")
    timing = need(report, "timing", dict, "report")
    for k in ("descriptors_s", "classification_s", "total_s"):
        need(timing or {}, k, NUMBER, "timing")
    for i, v in enumerate(need(report, "variants", list, "report") or []):
        where = f"variants[{i}]"
        name = need(v, "variant", str, where)
        need(v, "title", str, where)
        acc = need(v, "accuracy", NUMBER, where)
        if acc is not None and not 0 <= acc <= 1:
            problems.append(f"{where}.accuracy: {acc} is not in [0, 1]")
        need(v, "mean_fold_accuracy", NUMBER, where)
        need(v, "fold_accuracy", list, where)
        c = need(v, "confusion", dict, where) or {}
        labels = need(c, "labels", list, where + ".confusion") or []
        matrix = need(c, "matrix", list, where + ".confusion") or []
        if len(matrix) != len(labels) or any(len(r) != len(labels) for r in matrix):
            problems.append(f"{where}.confusion.matrix: not {len(labels)}x{len(labels)}")
        per_class = need(c, "per_class", dict, where + ".confusion") or {}
        for label in labels:
            pc = need(per_class, label, dict, where + ".confusion.per_class") or {}
            for k in ("precision", "recall"):
                need(pc, k, NUMBER, f"{where}.per_class.{label}")
            need(pc, "support", int, f"{where}.per_class.{label}")
        rel = need(c, "reliability", dict, where + ".confusion") or {}
        answers = need(rel, "answers", int, where + ".reliability")
        for k in ("mean_confidence", "expected_calibration_error"):
            x = need(rel, k, NUMBER, where + ".reliability")
            if x is not None and not 0 <= x <= 1:
                problems.append(f"{where}.reliability.{k}: {x} is not in [0, 1]")
        bins = need(rel, "bins", list, where + ".reliability") or []
        if len(bins) != 10:
            problems.append(f"{where}.reliability.bins: {len(bins)} bins, expected 10")
        elif answers is not None and sum(b.get("count", 0) for b in bins) != answers:
            problems.append(f"{where}.reliability.bins: counts do not add up to {answers} answers")
        if name:
            for ext in ("csv", "png"):
                f = os.path.join(out, f"confusion_{name}.{ext}")
                if not os.path.isfile(f):
                    problems.append(f"{f}: missing")
    if "frames_sweep" in report:
        s = report["frames_sweep"]
        n = len(need(s, "frames", list, "frames_sweep") or [])
        for k in ("sumflow", "sumflow_pca"):
            if len(need(s, k, list, "frames_sweep") or []) != n:
                problems.append(f"frames_sweep.{k}: length differs from frames")
        if not os.path.isfile(os.path.join(out, "accuracy_vs_frames.png")):
            problems.append("accuracy_vs_frames.png: missing")
    return problems


def main():
    out = sys.argv[1]
    try:
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        print(f"{out}/report.json: {e}")
        sys.exit(1)
    problems = check(report, out)
    for p in problems:
        print(p)
    if problems:
        sys.exit(1)
    print("report OK")


if __name__ == "__main__":
    main()
