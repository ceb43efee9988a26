#!/usr/bin/env bash
# Runs `catkin_lint -W2 --strict` on the package (every warning is an error) and writes a JUnit
# result for catkin's test summary; exits non-zero when catkin_lint finds a problem.
# Usage: run_catkin_lint.sh PACKAGE_DIR JUNIT_XML_PATH
# catkin_lint has no rosdep database on machines without internet (`rosdep update` fails there),
# so it cannot check that package.xml's keys resolve; it says so on stderr and checks the rest.
set -uo pipefail
package_dir=$1
junit=$2
mkdir -p "$(dirname "$junit")"
# The package folder's name must be the package's name (catkin_lint's package_path_name check):
# CMake passes the workspace's src/ohm_mirror_detector3d, not the repository's folder. That folder
# is made of links to the repository's entries, and catkin_lint does not walk into linked folders
# (it would not see, say, an executable script under bench/): it checks a real copy instead.
if command -v catkin_lint > /dev/null; then
  copy=$(mktemp -d)
  trap 'rm -rf "$copy"' EXIT
  cp -rL "$package_dir" "$copy/$(basename "$package_dir")"
  output=$(catkin_lint -W2 --strict "$copy/$(basename "$package_dir")" 2>&1)
  status=$?
else
  output="catkin_lint is not installed: apt-get install catkin-lint (rosdep key python3-catkin-lint)"
  status=1
fi
echo "$output"
escaped=$(printf '%s' "$output" | sed -e 's/&/\&amp;/g' -e 's/</\&lt;/g' -e 's/>/\&gt;/g' -e 's/"/\&quot;/g')
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  echo "<testsuite name=\"catkin_lint\" tests=\"1\" failures=\"$([ $status = 0 ] && echo 0 || echo 1)\" errors=\"0\">"
  echo '  <testcase classname="catkin_lint" name="strict">'
  [ $status = 0 ] || echo "    <failure message=\"catkin_lint -W2 --strict found problems\">$escaped</failure>"
  echo "    <system-out>$escaped</system-out>"
  echo '  </testcase>'
  echo '</testsuite>'
} > "$junit"
exit $status
