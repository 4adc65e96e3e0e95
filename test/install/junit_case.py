#!/usr/bin/env python3
"""Writes a JUnit file of one testcase, for the shell tests of test/install (catkin's run_tests
wrapper and scripts/test_summary.py read it).

    junit_case.py RESULT_XML SUITE CASE pass|fail|skipped SECONDS [MESSAGE]
"""
import sys
import xml.etree.ElementTree as ET

path, suite_name, case_name, status, secs = sys.argv[1:6]
message = sys.argv[6] if len(sys.argv) > 6 else ""
suite = ET.Element("testsuite", name=suite_name, tests="1", failures=str(int(status == "fail")),
                   errors="0", skipped=str(int(status == "skipped")), time=secs)
case = ET.SubElement(suite, "testcase", classname=suite_name, name=case_name, time=secs)
if status == "fail":
    ET.SubElement(case, "failure", message=message[:300]).text = message
elif status == "skipped":
    ET.SubElement(case, "skipped", message=message).text = message
ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
