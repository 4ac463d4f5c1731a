#!/usr/bin/env bash
# The test suite, from a fresh Debian machine: installs what is missing (as root, or names
# the packages), builds the debug preset (asserts on) and runs the tests through ctest.
#   scripts/test.sh                          # debug build, every test but those labelled slow
#   scripts/test.sh --all                    # every test, the slow ones too (CI runs this)
#   QUACK_PRESET=sanitize scripts/test.sh    # the same under address + UB sanitizers
# The slow tests (label `slow`): the add_subdirectory install round trip, the long thread,
# stacking and fuzz-like runs. `ctest --preset debug -L slow` runs only them.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${QUACK_PRESET:-debug}
filter=(-LE slow)
case "${1:-}" in
  --all) filter=() ;;
  "") ;;
  *) echo "test.sh: unknown option '$1' (expected --all or nothing)" >&2; exit 2 ;;
esac
scripts/setup.sh build test bench python
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset" "${filter[@]}"
