#!/usr/bin/env bash
# The same bits on every build we can run here (docs/determinism.md, "Builds"): builds the
# quack program in several configurations, runs every sample scene (scenes/*.json, the
# 2,000-shape scenes/random-2000.json among them) in each for the same number of steps and
# compares the state files and the event lists (`quack run --events`) byte for byte (they
# print every float exactly) with those of the g++ -O3 SSE2 build.
#
#   scripts/determinism.sh                 # all configurations this machine can build
#   QUACK_DETERMINISM_STEPS=300 QUACK_DETERMINISM_CONFIGS="avx2 scalar" scripts/determinism.sh
#
# Configurations: release (g++ -O3, SSE2 lanes: the reference), avx2 (QUACK_SIMD=avx2,
# when the CPU has AVX2), scalar (QUACK_SIMD=scalar), clang-release (clang -O3), debug
# (g++ -O0, asserts on), aarch64 (cross-compiled with g++-aarch64-linux-gnu, NEON lanes,
# run under qemu-aarch64-static) and wasm (the same program built with emscripten from
# web/CMakeLists.txt, scalar path, run under node with the real file system). aarch64 and
# wasm are skipped with a note when their tools are not installed. gcc-o2 and clang-o2 are
# the release builds at -O2 instead of -O3 (build/gcc-o2, build/clang-o2). threads runs the
# reference build's program on 4 workers (`--threads 4`; every other run uses one). Each
# configuration's build and run times are printed.
set -euo pipefail
# build() runs in a command substitution, where bash drops -e: without this a failed build
# went on with the program left from the last good one, and compared stale bits.
shopt -s inherit_errexit
cd "$(dirname "$0")/.."
steps=${QUACK_DETERMINISM_STEPS:-600}
configs=${QUACK_DETERMINISM_CONFIGS:-"threads avx2 scalar clang-release gcc-o2 clang-o2 debug aarch64 wasm"}
out=out/determinism
rm -rf "$out"
mkdir -p "$out"

say() { printf 'determinism: %s\n' "$*"; }

build() {  # build <name>: configures and builds the quack program; prints its path
  local name=$1
  case $name in
    aarch64)
      cmake -S . -B build/aarch64 -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
        -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF >/dev/null
      cmake --build build/aarch64 -j2 --target quack >&2
      echo "qemu-aarch64-static -L /usr/aarch64-linux-gnu build/aarch64/apps/quack/quack"
      ;;
    wasm)
      # Debian's emscripten runs its JavaScript optimiser with node and needs acorn, which
      # Debian keeps in /usr/share/nodejs (as scripts/web.sh does).
      export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
      if [ ! -f build/wasm/CMakeCache.txt ]; then
        emcmake cmake -S web -B build/wasm -DCMAKE_BUILD_TYPE=Release >/dev/null
      fi
      cmake --build build/wasm -j2 --target quack >&2
      echo "node build/wasm/quack-cli/quack.js"
      ;;
    threads)
      echo "build/release/apps/quack/quack"
      ;;
    gcc-o2 | clang-o2)
      # -O2 (the release presets are -O3), without tests or benchmarks.
      local compiler=g++
      [ "$name" = clang-o2 ] && compiler=clang++
      cmake -S . -B "build/$name" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_CXX_COMPILER=$compiler \
        -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF -DQUACK_BUILD_PYTHON=OFF >/dev/null
      cmake --build "build/$name" -j2 --target quack >&2
      echo "build/$name/apps/quack/quack"
      ;;
    *)
      cmake --preset "$name" >/dev/null
      cmake --build --preset "$name" --target quack >&2
      echo "build/$name/apps/quack/quack"
      ;;
  esac
}

run_all() {  # run_all <name> <command...>: every sample scene into $out/<name>/
  local name=$1 threads=1
  shift
  [ "$name" = threads ] && threads=4
  mkdir -p "$out/$name"
  for scene in scenes/*.json; do
    local base
    base=$(basename "$scene" .json)
    "$@" run "$scene" --steps "$steps" --threads "$threads" --out "$out/$name/$base.json" \
      --events "$out/$name/$base.events.jsonl" --quiet >/dev/null
  done
}

started=$SECONDS
reference=$(build release)
built=$SECONDS
run_all release $reference
say "reference: release (g++ -O3, SSE2), $(ls scenes/*.json | wc -l) scenes, $steps steps" \
  "(build $((built - started)) s, runs $((SECONDS - built)) s)"

failed=0
for name in $configs; do
  if [ "$name" = avx2 ] && ! grep -qw avx2 /proc/cpuinfo; then
    say "avx2: skipped (this CPU has no AVX2)"
    continue
  fi
  if [ "$name" = aarch64 ] && ! { command -v aarch64-linux-gnu-g++ && command -v qemu-aarch64-static; } >/dev/null; then
    say "aarch64: skipped (apt-get install g++-aarch64-linux-gnu qemu-user-static)"
    continue
  fi
  if [ "$name" = wasm ] && ! { command -v emcmake && command -v node; } >/dev/null; then
    say "wasm: skipped (scripts/setup.sh web installs emscripten and node)"
    continue
  fi
  started=$SECONDS
  program=$(build "$name")
  built=$SECONDS
  run_all "$name" $program
  differ=0
  for f in "$out/release"/*; do
    if ! cmp -s "$f" "$out/$name/$(basename "$f")"; then
      say "$name: $(basename "$f") differs from release"
      differ=1
    fi
  done
  times="build $((built - started)) s, runs $((SECONDS - built)) s"
  if [ $differ -eq 0 ]; then
    say "$name: every state file and event list identical to release ($times)"
  else
    say "$name: differs ($times)"
    failed=1
  fi
done
exit $failed
