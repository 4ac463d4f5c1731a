#!/usr/bin/env bash
# The main job, from a fresh Debian machine: installs what is missing (as root, or names
# the packages), builds the release preset and runs the shapes tour, which prints hulls,
# mass properties, bounding boxes and a ray cast beside the answers worked out by hand.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
cmake --preset release -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build --preset release --target quack_shapes_tour
./build/release/examples/quack_shapes_tour
