#!/usr/bin/env bash
# Set up, build, and run every test (fast and slow) through CTest.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
ctest --test-dir "$TB_ROOT/build" --output-on-failure -j"$(nproc)" --timeout 1500
