#!/usr/bin/env bash
# The long fuzz run: tests/fuzz with SCALE times the CI's examples (default 50) and fresh
# randomness each run; hypothesis keeps failures in .hypothesis/ and replays them first.
#   scripts/fuzz.sh            # 50x: xacro, URDF, SDF, launch 10000 examples each, messages 30000,
#                              #   maps 25000 (YAML 7500, images 12500, PNG headers 5000),
#                              #   ROS 1 bags and MCAP files 7500 each, SLAM input (gmapping
#                              #   7500, hector 5000, amcl + a costmap 5000), a live Foxglove
#                              #   bridge 7500
#   scripts/fuzz.sh 200 -k sdf # 200x, only the SDF fuzzer
set -euo pipefail
cd "$(dirname "$0")/.."
scale="${1:-50}"
shift || true
BELVEDERE_FUZZ_SCALE="$scale" python -m pytest -q -p no:logging tests/fuzz \
    --hypothesis-show-statistics "$@"
