#!/usr/bin/env bash
# rosrun finds the package's tools in the devel space, as a user runs them after scripts/setup and
# `source devel/setup.bash` (rosrun skips everything below <package>/build/, which is why the devel
# space is <package>/devel): train, evaluate and synth print their help, and the user script
# label_bag.py is found. Writes one JUnit testcase into RESULT_XML.
#
#   test/install/test_devel_rosrun.sh DEVEL_DIR RESULT_XML
set -u
DEVEL="$(cd "${1:?devel space}" && pwd)"
RESULT="${2:?result file}"
export PATH=/usr/bin:/bin:$PATH
mkdir -p "$(dirname "$RESULT")"
TMP="$(mktemp -d -t action_flow_rosrun.XXXXXX)"
trap 'rm -rf "$TMP"' EXIT

status=pass
message=""
start=$(date +%s.%N)
for tool in train evaluate synth label_bag.py; do
  # A clean environment with only the devel space's setup.bash sourced.
  if ! env -i HOME="$TMP" PATH=/usr/bin:/bin LANG=C.UTF-8 bash -c \
      "source '$DEVEL/setup.bash' && rosrun action_flow $tool --help" >"$TMP/out" 2>&1; then
    status=fail
    message="rosrun action_flow $tool --help failed: $(head -c 400 "$TMP/out")"
    echo "[  FAILED  ] devel.rosrun: $message"
    break
  fi
done
[ "$status" = pass ] && echo "[  PASSED  ] devel.rosrun: train, evaluate, synth, label_bag.py"
secs=$(/usr/bin/python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$start" "$(date +%s.%N)")
/usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/junit_case.py" "$RESULT" devel_rosrun rosrun_finds_the_tools "$status" "$secs" "$message"
[ "$status" != fail ]
