#!/usr/bin/env bash
# The long fuzz run: tests/fuzz with SCALE times the CI's examples (default 50) and fresh
# randomness each run; hypothesis keeps failures in .hypothesis/ and replays them first.
#   scripts/fuzz.sh            # 50x: xacro, URDF, SDF, launch 10000 examples each, messages 30000,
#                              # SLAM input: gmapping 7500, hector 5000, amcl + a costmap 5000
#   scripts/fuzz.sh 200 -k sdf # 200x, only the SDF fuzzer
set -euo pipefail
cd "$(dirname "$0")/.."
scale="${1:-50}"
shift || true
BELVEDERE_FUZZ_SCALE="$scale" python -m pytest -q -p no:logging tests/fuzz \
    --hypothesis-show-statistics "$@"
