#!/usr/bin/env bash
# The main job, from a fresh Debian machine: installs what is missing (as root, or names
# the packages), builds the release preset's quack program, and simulates a 20-row pyramid
# of boxes for 10 seconds with `quack run`. It prints a summary and writes, in out/:
#   pyramid.state.json  where every body ended and event counts (timing: the summary)
#   pyramid.svg         a picture of the last state
#   pyramid.html        a self-contained replay (open it in a browser: play, pause, scrub, zoom)
# Another scene:  scripts/run.sh scenes/rain.json 900
# A 3D scene ("dim": 3; its replay is drawn with WebGL and it has no SVG):
#                 scripts/run.sh scenes/cards-3d.json
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/pyramid.json}
steps=${2:-600}
name=$(basename "$scene" .json)
scripts/setup.sh build
cmake --preset release -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build --preset release --target quack
mkdir -p out
if grep -Eq '"dim"[[:space:]]*:[[:space:]]*3' "$scene"; then
  ./build/release/apps/quack/quack run "$scene" --steps "$steps" --out "out/$name.state.json" \
    --html "out/$name.html"
  echo
  echo "Open out/$name.html in a browser to watch the run (drag to orbit, wheel to zoom)."
else
  ./build/release/apps/quack/quack run "$scene" --steps "$steps" --out "out/$name.state.json" \
    --svg "out/$name.svg" --html "out/$name.html"
  echo
  echo "Open out/$name.html in a browser to watch the run (out/$name.svg is the last frame)."
fi
