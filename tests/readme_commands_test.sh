#!/usr/bin/env bash
# The README's quick-start test command must be the one .ci/run executes.
set -euo pipefail
cd "$1"
ci_command=$(grep -E '^scripts/bootstrap.sh && ctest' .ci/run)
grep -qF "$ci_command" README.md || { echo "README does not contain the CI test command: $ci_command"; exit 1; }
grep -qE '^scripts/bootstrap.sh && build/bin/slamkit ' README.md || { echo "README lacks the main-job command"; exit 1; }
echo "README and .ci/run agree: $ci_command"
