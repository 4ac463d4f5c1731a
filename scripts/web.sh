#!/usr/bin/env bash
# The web demo (docs/web-demo.md): builds Quack to WebAssembly with Debian's emscripten,
# stages the pages in build/web-site, and optionally serves or tests them.
#   scripts/web.sh                 # install what is missing, build into build/web-site
#   scripts/web.sh --serve [PORT]  # install, build, then serve on http://localhost:PORT (8000)
#   scripts/web.sh --test          # install, build, run the browser tests
# Every mode installs the Debian packages it needs first (scripts/setup.sh build web: as
# root it installs them, otherwise it names the command to run), so each works on a fresh
# machine.
# Build folders: build/wasm (emscripten), build/web-native (the native `quack` program the
# tests compare against), build/web-site (what is served).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
mode=build
port=8000
case "${1:-}" in
  "") ;;
  --serve) mode=serve; port=${2:-8000} ;;
  --test) mode=test ;;
  *) echo "usage: scripts/web.sh [--serve [PORT] | --test]" >&2; exit 2 ;;
esac
jobs=${QUACK_WEB_JOBS:-2}
say() { printf 'web.sh: %s\n' "$*" >&2; }

case "$port" in
  '' | *[!0-9]*) say "--serve: $port is not a port number"; exit 2 ;;
esac
# Every mode needs emscripten (and --serve python3, --test chromium and node): install
# what is missing, as --test always did; setup.sh names the command when not root.
scripts/setup.sh build web
command -v emcmake >/dev/null || { say "emscripten missing after scripts/setup.sh build web"; exit 1; }

# Debian's emscripten runs its JavaScript optimiser (above -O1) with node and needs acorn,
# which Debian keeps in /usr/share/nodejs.
export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}

say "WebAssembly build (build/wasm)"
if [ ! -f build/wasm/CMakeCache.txt ]; then
  emcmake cmake -S web -B build/wasm -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build build/wasm -j"$jobs"

# The npm packages, pinned by web/package-lock.json: three (the 3D page draws with it; the
# site serves its own copy, nothing is loaded from the network) and playwright-core (the
# tests; no browser is downloaded).
say "npm ci (three, playwright-core; no browser is downloaded)"
(cd web && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error)

say "staging build/web-site"
site=build/web-site
rm -rf "$site"
mkdir -p "$site/js/vendor/three/addons/controls" "$site/js/vendor/three/addons/geometries" \
  "$site/js/vendor/three/addons/math"
cp web/*.html web/style.css "$site/"
cp web/js/*.js "$site/js/"
cp build/wasm/quack_web.js build/wasm/quack_web.wasm "$site/"
# The 3D sample scenes, which the 3D sandbox page loads (sandbox3d.html).
mkdir -p "$site/scenes"
cp scenes/*-3d.json "$site/scenes/"
# three.js as ES modules (the pages' import map names "three" and "three/addons/").
three=web/node_modules/three
cp "$three/build/three.module.js" "$three/build/three.core.js" "$three/LICENSE" \
  "$site/js/vendor/three/"
for addon in controls/OrbitControls.js geometries/ConvexGeometry.js math/ConvexHull.js; do
  cp "$three/examples/jsm/$addon" "$site/js/vendor/three/addons/$addon"
done

case "$mode" in
  serve)
    say "serving http://localhost:$port/ (index.html: GJK and EPA; gjk3d.html: the same in 3D; sandbox.html: world; sandbox3d.html: 3D world); Ctrl-C stops"
    exec python3 -m http.server "$port" --bind 127.0.0.1 --directory "$site"
    ;;
  test)
    say "native quack program (build/web-native)"
    if [ ! -f build/web-native/CMakeCache.txt ]; then
      cmake -S . -B build/web-native -DCMAKE_BUILD_TYPE=Release -DQUACK_BUILD_TESTS=OFF \
        -DQUACK_BUILD_BENCHMARKS=OFF -DQUACK_BUILD_APPS=ON >/dev/null
    fi
    cmake --build build/web-native --target quack -j"$jobs"
    say "browser tests (headless chromium)"
    export QUACK_WEB_SITE="$root/$site"
    export QUACK_BIN="$root/build/web-native/apps/quack/quack"
    cd web && node --test --test-concurrency=1 tests/*.test.mjs
    ;;
esac
