#!/usr/bin/env bash
# Runs the pytest suite with Debian's interpreter (the pyenv python3 on PATH cannot see
# ROS). Usage: run_pytest.sh JUNIT_XML_PATH
set -euo pipefail
cd "$(dirname "$0")/.."
exec /usr/bin/python3 -m pytest test/python -q -p no:cacheprovider --junitxml="$1"
