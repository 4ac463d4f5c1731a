#!/usr/bin/env bash
# The whole test suite, from a fresh Debian machine: installs what is missing (as root, or
# names the packages), builds the debug preset (asserts on) and runs every test.
#   scripts/test.sh            # debug build, all tests
#   QUACK_PRESET=sanitize scripts/test.sh   # the same under address + UB sanitizers
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${QUACK_PRESET:-debug}
scripts/setup.sh build test bench python
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset"
