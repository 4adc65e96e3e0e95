#!/usr/bin/python3
"""Plays one bag through the nodelet pipeline as a user would (roslaunch action_flow bag.launch),
or a fakenect dump folder (roslaunch action_flow kinect.launch backend:=freenect device_uri:=DIR),
and prints the label of the person it saw longest: "<label> <confidence> <margin>". The labels of
every track that ends come within a few seconds of each other at the end of the input; of those,
the one with the longest window wins (a short second track, e.g. the tracker splitting a moving
arm off for a while, does not speak for the performer).

usage: label_bag.py BAG|DUMP_DIR MODEL [--input images|cloud] [--port PORT] [--timeout SECONDS]

Exits 1 with one line on stderr if no label came within the timeout or the launch failed."""
import argparse
import os
import re
import signal
import subprocess
import sys
import threading
import time


def stop_launch(proc):
    """Stops a roslaunch started in its own process group: SIGINT (a clean shutdown), SIGKILL after 20 s."""
    try:
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait(timeout=20)
    except (subprocess.TimeoutExpired, ProcessLookupError):
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bag")
    ap.add_argument("model")
    ap.add_argument("--input", default="images", choices=["images", "cloud"])
    ap.add_argument("--port", type=int, default=11411, help="ROS master port (own master per run)")
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args()
    dump = os.path.isdir(args.bag)
    for path, what in ((args.bag, "bag"), (args.model, "model")):
        if not (os.path.isfile(path) or (dump and path == args.bag)):
            sys.exit(f"label_bag: {what} file '{path}' does not exist")
    recording = os.path.abspath(args.bag)  # roslaunch nodes run in ~/.ros

    # Debian's ROS nodes start with "#!/usr/bin/env python3": the system Python must come first.
    env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{args.port}",
               PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""))
    # Rendered people: no HOG (PCL's classifier rejects them), as bag.launch's default.
    source = (["kinect.launch", "backend:=freenect", f"device_uri:={recording}", "hog:=off", "annotate:=false"] if dump
              else ["bag.launch", f"bag:={recording}", f"input:={args.input}"])
    cmd = ["roslaunch", "-p", str(args.port), "action_flow"] + source + [
           f"model:={os.path.abspath(args.model)}", "mode:=segmented", "echo_labels:=true"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                            start_new_session=True)
    labels = []  # one dict per ActionLabel echoed: label, confidence, margin, duration
    log = []
    first = []   # when the first label came (monotonic seconds)

    def read():
        current, stamp = {}, None
        for line in proc.stdout:
            log.append(line)
            s = line.strip()
            if s in ("window_start:", "window_end:"):
                stamp = s[:-1]
                continue
            m = re.match(r'^(secs|nsecs): (\d+)$', s)
            if m and stamp:
                current[stamp] = current.get(stamp, 0.0) + int(m.group(2)) * (1e-9 if m.group(1) == "nsecs" else 1.0)
                continue
            for key in ("label", "confidence", "margin"):
                m = re.match(rf'^{key}: "?([^"\n]*)"?\s*$', s)
                if m:
                    current[key] = m.group(1)
            if s == "---" and "margin" in current:
                current["duration"] = current.get("window_end", 0.0) - current.get("window_start", 0.0)
                labels.append(current)
                if not first:
                    first.append(time.monotonic())
                current, stamp = {}, None

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    deadline = time.monotonic() + args.timeout
    while reader.is_alive() and time.monotonic() < deadline and not (first and time.monotonic() > first[0] + 4.0):
        time.sleep(0.1)
    stop_launch(proc)
    if not labels:
        tail = "".join(log[-15:])
        sys.exit(f"label_bag: no label for '{args.bag}' within {args.timeout:.0f} s; launch output ended with:\n{tail}")
    found = max(labels, key=lambda l: l["duration"])
    print(found["label"], found["confidence"], found["margin"])


if __name__ == "__main__":
    main()
