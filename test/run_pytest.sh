#!/usr/bin/env bash
# Runs pytest with Debian's interpreter (the pyenv python3 on PATH cannot see ROS).
# Usage: run_pytest.sh JUNIT_XML_PATH [PYTEST_ARGS...]   (default: the whole of test/python)
set -euo pipefail
cd "$(dirname "$0")/.."
junit=$1
shift
[ $# -gt 0 ] || set -- test/python
exec /usr/bin/python3 -m pytest "$@" -q -p no:cacheprovider --junitxml="$junit"
