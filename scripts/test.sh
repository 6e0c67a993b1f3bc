#!/usr/bin/env bash
# The project's test command: lint, types, tests. Fails if any fails or if no test ran.
set -euo pipefail
cd "$(dirname "$0")/.."
ruff check src tests benchmarks examples
ruff format --check src tests benchmarks examples
mypy
# pytest exits 5 when it collected no tests; with `set -e` that fails this script too.
python -m pytest -q "$@"
