#!/usr/bin/env bash
# catkin_lint -W2 --strict on the package (Debian's catkin-lint, which scripts/setup installs):
# any error, warning or notice fails. Offline (no package index is downloaded); the rosdep database
# is not used, so catkin_lint does not resolve system dependencies. Writes one JUnit testcase into
# RESULT_XML; with catkin_lint absent the testcase is skipped, with the reason.
#
#   test/install/test_catkin_lint.sh SOURCE_DIR RESULT_XML
set -u
SRC="$(cd "${1:?package folder}" && pwd)"
RESULT="${2:?result file}"
export PATH=/usr/bin:/bin:$PATH
mkdir -p "$(dirname "$RESULT")"
TMP="$(mktemp -d -t action_flow_lint.XXXXXX)"
trap 'rm -rf "$TMP"' EXIT

status=pass
message=""
start=$(date +%s.%N)
if ! command -v catkin_lint >/dev/null; then
  status=skipped
  message="catkin_lint is not installed (Debian package catkin-lint; scripts/setup installs it)"
  echo "[  SKIPPED ] lint.catkin_lint: $message"
else
  # A clean environment: the result does not depend on the caller's ROS setup or rosdep cache.
  # The package is linted under its own name (a link), as in a workspace's src/action_flow, so that
  # the checkout's folder name (main, ...) is not reported.
  ln -s "$SRC" "$TMP/action_flow"
  env -i HOME="$TMP" PATH=/usr/bin:/bin LANG=C.UTF-8 \
    catkin_lint -W2 --strict --offline --color never "$TMP/action_flow" >"$TMP/out" 2>"$TMP/err"
  rc=$?
  if [ $rc != 0 ] || grep -qE ': (error|warning|notice): ' "$TMP/out"; then
    status=fail
    message="catkin_lint -W2 --strict exit $rc: $(grep -E ': (error|warning|notice): ' "$TMP/out" | head -n 30)"
    cat "$TMP/out"
    echo "[  FAILED  ] lint.catkin_lint"
  else
    echo "[  PASSED  ] lint.catkin_lint: $(grep -o "found [0-9]* problems" "$TMP/err")"
  fi
fi
secs=$(/usr/bin/python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$start" "$(date +%s.%N)")
/usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/junit_case.py" "$RESULT" catkin_lint catkin_lint_W2_strict "$status" "$secs" "$message"
[ "$status" != fail ]
