#!/usr/bin/python3
"""Reads the JUnit files that catkin's run_tests wrote and prints one summary line.

Exits 1 if any test failed or errored, or if no test ran at all."""
import glob
import os
import sys
import xml.etree.ElementTree as ET

root = sys.argv[1] if len(sys.argv) > 1 else "build/test_results"
passed = failed = skipped = 0
bad = []
for path in sorted(glob.glob(os.path.join(root, "**", "*.xml"), recursive=True)):
    try:
        tree = ET.parse(path)
    except ET.ParseError as e:
        failed += 1
        bad.append(f"{os.path.basename(path)}: unreadable result file ({e})")
        continue
    for case in tree.iter("testcase"):
        name = f"{case.get('classname', '')}.{case.get('name', '')}"
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
            bad.append(name)
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            skipped += 1
        else:
            passed += 1

for b in bad:
    print(f"FAILED: {b}")
print(f"tests: {passed} passed, {failed} failed, {skipped} skipped")
sys.exit(1 if failed or passed == 0 else 0)
