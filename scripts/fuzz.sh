#!/bin/sh
# Builds Quack's libFuzzer targets with clang in build/fuzz and runs each for a bounded
# time: QUACK_FUZZ_SECONDS (default 60) per target. Exits non-zero on the first crash.
set -eu
cd "$(dirname "$0")/.."
seconds="${QUACK_FUZZ_SECONDS:-60}"
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DQUACK_BUILD_FUZZERS=ON -DQUACK_ENABLE_ASSERTS=ON -DQUACK_SANITIZE=ON \
  -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF -DQUACK_BUILD_APPS=OFF >/dev/null
cmake --build build/fuzz -j 2 --target narrowphase_fuzzer scene_fuzzer
for fuzzer in narrowphase_fuzzer scene_fuzzer; do
  corpus="build/fuzz/corpus/$fuzzer"
  mkdir -p "$corpus"
  # Each starts from its committed seeds: the scene parser from the sample scenes
  # (fuzz/scene_seeds), the narrow phase from query lines (fuzz/narrowphase_seeds).
  [ "$fuzzer" = scene_fuzzer ] && cp fuzz/scene_seeds/*.json "$corpus"/
  [ "$fuzzer" = narrowphase_fuzzer ] && cp fuzz/narrowphase_seeds/* "$corpus"/
  echo "fuzz: $fuzzer for ${seconds}s"
  "build/fuzz/fuzz/$fuzzer" -max_total_time="$seconds" -print_final_stats=1 "$corpus"
done
