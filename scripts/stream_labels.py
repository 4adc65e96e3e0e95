#!/usr/bin/python3
"""Plays a continuous stream's bag through the nodelet pipeline in online mode, as a user would
(roslaunch action_flow bag.launch mode:=online), listens to the labels, and prints a timeline of
the truth (the stream's segments CSV, written by `synth --dataset stream`) against what was
recognised: each true action with the label published for it, and every label published while
nobody acted.

usage: stream_labels.py BAG MODEL SEGMENTS_CSV [--port PORT] [--timeout SECONDS]

Prints the timeline, then one line "recognised R of N actions, F false labels". Exits 1 with one
line on stderr if the launch failed or a file is missing or malformed."""
import argparse
import csv
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))  # label_bag.py lies beside this script
from label_bag import stop_launch  # noqa: E402


def read_segments(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        return [(r["action"], float(r["start"]), float(r["end"])) for r in rows]
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f"stream_labels: {path}: not a segments CSV (action,first_frame,last_frame,start,end): {e}")


def overlap(a0, a1, b0, b1):
    return max(0.0, min(a1, b1) - max(a0, b0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bag")
    ap.add_argument("model")
    ap.add_argument("segments")
    ap.add_argument("--port", type=int, default=11711, help="ROS master port (own master per run)")
    ap.add_argument("--timeout", type=float, default=300.0)
    args = ap.parse_args()
    for path, what in ((args.bag, "bag"), (args.model, "model"), (args.segments, "segments CSV")):
        if not os.path.isfile(path):
            sys.exit(f"stream_labels: {what} file '{path}' does not exist")
    truth = read_segments(args.segments)

    # Debian's ROS nodes start with "#!/usr/bin/env python3": the system Python must come first.
    os.environ["ROS_MASTER_URI"] = f"http://localhost:{args.port}"
    os.environ["PATH"] = "/usr/bin:/bin:" + os.environ.get("PATH", "")
    import rosbag
    import rospy
    from action_flow.msg import ActionLabel

    with rosbag.Bag(args.bag) as b:
        bag_seconds = b.get_end_time() - b.get_start_time()
    cmd = ["roslaunch", "-p", str(args.port), "action_flow", "bag.launch", f"bag:={os.path.abspath(args.bag)}",
           f"model:={os.path.abspath(args.model)}", "input:=images", "mode:=online", "echo_labels:=false"]
    log = open(os.devnull, "w")
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    labels = []  # (published, label, confidence, start, end)
    try:
        deadline = time.monotonic() + 30.0
        while True:  # wait for the master
            try:
                rospy.init_node("stream_labels", anonymous=True, disable_signals=True)
                break
            except Exception:
                if time.monotonic() > deadline or proc.poll() is not None:
                    sys.exit("stream_labels: the launch did not start (roslaunch " + " ".join(cmd[2:]) + ")")
                time.sleep(0.5)

        def on_label(m):
            if m.mode == ActionLabel.ONLINE_END:
                for i in range(len(labels) - 1, -1, -1):
                    if labels[i][1] == m.label and m.track_id == labels[i][5]:
                        labels[i] = labels[i][:4] + (m.window_end.to_sec(), m.track_id)
                        break
            else:
                labels.append((m.header.stamp.to_sec(), m.label, m.confidence, m.window_start.to_sec(),
                               m.window_end.to_sec(), m.track_id))

        rospy.Subscriber("/action_flow/labels", ActionLabel, on_label, queue_size=50)
        # The bag plays after a 1 s delay at its own rate; a few seconds more for the last labels.
        end = time.monotonic() + min(args.timeout, bag_seconds + 12.0)
        while time.monotonic() < end and proc.poll() is None:
            time.sleep(0.2)
    finally:
        stop_launch(proc)

    t0 = min([s for _, s, _ in truth] + [l[3] for l in labels]) if truth or labels else 0.0
    assigned = {i: [] for i in range(len(truth))}
    false = []
    for l in labels:
        best = max(range(len(truth)), key=lambda i: overlap(truth[i][1], truth[i][2], l[3], l[4]), default=None)
        if best is not None and overlap(truth[best][1], truth[best][2], l[3], l[4]) > 0:
            assigned[best].append(l)
        else:
            false.append(l)
    print(f"{'time (s)':>13}  {'truth':<16} recognised")
    events = [(s, "truth", i) for i, (_, s, _) in enumerate(truth)] + [(l[0], "false", l) for l in false]
    right = 0
    for at, kind, item in sorted(events, key=lambda e: e[0]):
        if kind == "truth":
            action, s, e = truth[item]
            got = ", ".join(f"{l[1]} at {l[0] - t0:.1f} s ({l[2]:.2f})" for l in assigned[item]) or "-"
            ok = any(l[1] == action for l in assigned[item])
            right += ok
            print(f"{s - t0:6.1f}-{e - t0:6.1f}  {action:<16} {got}{'' if ok else '   <- missed'}")
        else:
            print(f"{item[3] - t0:6.1f}-{item[4] - t0:6.1f}  {'(nobody acts)':<16} {item[1]} at {item[0] - t0:.1f} s "
                  f"({item[2]:.2f})   <- false")
    wrong = sum(1 for i in assigned for l in assigned[i] if l[1] != truth[i][0])
    print(f"recognised {right} of {len(truth)} actions, {len(false) + wrong} false labels")


if __name__ == "__main__":
    main()
