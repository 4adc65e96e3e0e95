#!/usr/bin/python3
"""Plays one bag through the nodelet pipeline as a user would (roslaunch action_flow bag.launch)
and prints the first action label it publishes: "<label> <confidence> <margin>".

usage: label_bag.py BAG MODEL [--input images|cloud] [--port PORT] [--timeout SECONDS]

Exits 1 with one line on stderr if no label came within the timeout or the launch failed."""
import argparse
import os
import re
import signal
import subprocess
import sys
import threading
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bag")
    ap.add_argument("model")
    ap.add_argument("--input", default="images", choices=["images", "cloud"])
    ap.add_argument("--port", type=int, default=11411, help="ROS master port (own master per run)")
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args()
    for path, what in ((args.bag, "bag"), (args.model, "model")):
        if not os.path.isfile(path):
            sys.exit(f"label_bag: {what} file '{path}' does not exist")

    # Debian's ROS nodes start with "#!/usr/bin/env python3": the system Python must come first.
    env = dict(os.environ, ROS_MASTER_URI=f"http://localhost:{args.port}",
               PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""))
    cmd = ["roslaunch", "-p", str(args.port), "action_flow", "bag.launch", f"bag:={args.bag}",
           f"model:={args.model}", f"input:={args.input}", "mode:=segmented", "echo_labels:=true"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                            start_new_session=True)
    found = {}
    log = []

    def read():
        for line in proc.stdout:
            log.append(line)
            for key in ("label", "confidence", "margin"):
                m = re.match(rf'^{key}: "?([^"\n]*)"?\s*$', line.strip())
                if m and key not in found:
                    found[key] = m.group(1)
            if "margin" in found:
                return

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(args.timeout)
    try:
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait(timeout=20)
    except (subprocess.TimeoutExpired, ProcessLookupError):
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    if "margin" not in found:
        tail = "".join(log[-15:])
        sys.exit(f"label_bag: no label for '{args.bag}' within {args.timeout:.0f} s; launch output ended with:\n{tail}")
    print(found["label"], found["confidence"], found["margin"])


if __name__ == "__main__":
    main()
