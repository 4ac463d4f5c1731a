#!/usr/bin/env bash
# The same bits on every build we can run here (docs/world.md, "Determinism"): builds the
# quack program in several configurations, runs every sample scene in each for the same
# number of steps and compares the state files byte for byte (they print every float
# exactly) with those of the g++ -O3 SSE2 build.
#
#   scripts/determinism.sh                 # all configurations this machine can build
#   QUACK_DETERMINISM_STEPS=300 QUACK_DETERMINISM_CONFIGS="avx2 scalar" scripts/determinism.sh
#
# Configurations: release (g++ -O3, SSE2 lanes: the reference), avx2 (QUACK_SIMD=avx2,
# when the CPU has AVX2), scalar (QUACK_SIMD=scalar), clang-release (clang -O3), debug
# (g++ -O0, asserts on) and aarch64 (cross-compiled with g++-aarch64-linux-gnu, NEON lanes,
# run under qemu-aarch64-static; skipped with a note when those are not installed).
set -euo pipefail
cd "$(dirname "$0")/.."
steps=${QUACK_DETERMINISM_STEPS:-600}
configs=${QUACK_DETERMINISM_CONFIGS:-"avx2 scalar clang-release debug aarch64"}
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
    *)
      cmake --preset "$name" >/dev/null
      cmake --build --preset "$name" --target quack >&2
      echo "build/$name/apps/quack/quack"
      ;;
  esac
}

run_all() {  # run_all <name> <command...>: every sample scene into $out/<name>/
  local name=$1
  shift
  mkdir -p "$out/$name"
  for scene in scenes/*.json; do
    "$@" run "$scene" --steps "$steps" --out "$out/$name/$(basename "$scene")" --quiet >/dev/null
  done
}

reference=$(build release)
run_all release $reference
say "reference: release (g++ -O3, SSE2), $(ls scenes/*.json | wc -l) scenes, $steps steps"

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
  program=$(build "$name")
  run_all "$name" $program
  differ=0
  for f in "$out/release"/*.json; do
    if ! cmp -s "$f" "$out/$name/$(basename "$f")"; then
      say "$name: $(basename "$f") differs from release"
      differ=1
    fi
  done
  if [ $differ -eq 0 ]; then
    say "$name: every state file identical to release"
  else
    failed=1
  fi
done
exit $failed
