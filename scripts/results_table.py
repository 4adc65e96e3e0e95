#!/usr/bin/python3
"""Prints the README's result tables (markdown) from the report folders that
scripts/run_experiments writes: results_ias_12x15x3 and results_msr_{all,as1,as2,as3}.
Usage: results_table.py FOLDER (the folder holding the report folders)."""
import json
import os
import sys

VARIANTS = [("posture_flow", "**posture_flow (default)**"),
            ("posture_flow_no_posture", "posture_flow without posture"),
            ("posture_flow_choose_posture", "posture_flow, posture chosen by cross-validation"),
            ("posture_flow_no_geometry", "posture_flow without the body geometry"),
            ("posture_flow_sums", "posture_flow, always signed flow sums"),
            ("posture_flow_bins", "posture_flow, always direction bins"),
            ("posture_flow_single_level", "posture_flow, 4x4x4 grid only"),
            ("posture_flow_no_pyramid", "posture_flow, whole-sequence mean only"),
            ("posture_flow_means_only", "posture_flow, pyramid of means only (no maxima, no Fourier)"),
            ("posture_flow_no_fourier", "posture_flow, pyramid of means and maxima (no Fourier)"),
            ("posture_flow_nn", "posture_flow, 1-NN instead of the linear classifier"),
            ("posture_flow_no_mirror", "posture_flow, never mirrored training copies"),
            ("posture_flow_mirror", "posture_flow, always mirrored training copies"),
            ("meanflow", "paper: MEANFLOW"), ("sumflow_raw", "paper: SUMFLOW without outlier rejection"),
            ("sumflow", "paper: SUMFLOW"), ("sumflow_pca", "paper: SUMFLOW with PCA (99%)"),
            ("joints", "joint-position baseline (skeleton files)")]
PAPER_IAS = {"meanflow": "58.0%", "sumflow_raw": "81.9%", "sumflow": "85.2%", "sumflow_pca": "87.4%"}


def present(reports, key):
    return any(accuracy(r, key) != "-" for r in reports)


def load(folder, name):
    path = os.path.join(folder, name, "report.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def accuracy(report, variant):
    for v in report["variants"]:
        if v["variant"] == variant:
            return "%.1f%%" % (100.0 * v["accuracy"])
    return "-"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: results_table.py FOLDER")
    folder = sys.argv[1]
    ias = load(folder, "results_ias_12x15x3")
    if ias:
        t = ias["timing"]
        print("Leave-one-person-out, synthetic IAS-Lab-style set: %d samples, %d people, %d folds; "
              "%.0f s in all (%.0f s descriptors, %d jobs)\n" % (
                  ias["samples"]["total"], ias["samples"]["people"], ias["folds"], t["total_s"],
                  t["descriptors_s"], t["jobs"]))
        print("| variant | ours | paper (IAS-Lab) |\n|---|---|---|")
        for key, title in VARIANTS:
            if present([ias], key):
                print("| %s | %s | %s |" % (title, accuracy(ias, key), PAPER_IAS.get(key, "")))
        print()
    msr = [(name, load(folder, "results_msr_" + name.lower())) for name in ("AS1", "AS2", "AS3", "all")]
    msr = [(n, r) for n, r in msr if r]
    if msr:
        print("MSR Action3D, cross-subject (train s01,s03,s05,s07,s09), skeletons rendered by the virtual Kinect\n")
        print("| variant | " + " | ".join("%s (%d seq.)" % (n, r["samples"]["total"]) for n, r in msr) + " |")
        print("|---|" + "---|" * len(msr))
        for key, title in VARIANTS:
            if present([r for _, r in msr], key):
                print("| %s | %s |" % (title, " | ".join(accuracy(r, key) for _, r in msr)))
        print("\nPublished, real data: bag of 3D points 74.7% (mean of AS1-3); on all 20 actions "
              "Actionlet Ensemble 88.2%, HON4D 88.9%, Lie group skeletons 89.5%.")


if __name__ == "__main__":
    main()
