#!/bin/sh
# Builds Quack's libFuzzer targets with clang in build/fuzz and runs each for a bounded
# time: QUACK_FUZZ_SECONDS (default 60) per target, QUACK_FUZZ_TARGETS (default all three)
# to pick. Exits non-zero on the first crash.
set -eu
cd "$(dirname "$0")/.."
seconds="${QUACK_FUZZ_SECONDS:-60}"
targets="${QUACK_FUZZ_TARGETS:-narrowphase_fuzzer scene_fuzzer snapshot_fuzzer}"
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DQUACK_BUILD_FUZZERS=ON -DQUACK_ENABLE_ASSERTS=ON -DQUACK_SANITIZE=ON \
  -DQUACK_BUILD_TESTS=OFF -DQUACK_BUILD_BENCHMARKS=OFF -DQUACK_BUILD_APPS=OFF >/dev/null
# shellcheck disable=SC2086
cmake --build build/fuzz -j 2 --target $targets
for fuzzer in $targets; do
  corpus="build/fuzz/corpus/$fuzzer"
  mkdir -p "$corpus"
  # Each starts from its committed seeds, kept in the repository: the scene parser from
  # fuzz/scene_seeds (every sample scene and the regression inputs of tests/io/bad_scenes),
  # the narrow phase from fuzz/narrowphase_seeds (query lines); the snapshot fuzzer makes
  # its seed snapshots at start-up (fuzz/snapshot_fuzzer.cpp) and takes the inputs that once
  # failed from fuzz/snapshot_seeds (edits of those snapshots); new finds go to $corpus.
  seeds=""
  [ "$fuzzer" = scene_fuzzer ] && seeds=fuzz/scene_seeds
  [ "$fuzzer" = narrowphase_fuzzer ] && seeds=fuzz/narrowphase_seeds
  [ "$fuzzer" = snapshot_fuzzer ] && seeds=fuzz/snapshot_seeds
  echo "fuzz: $fuzzer for ${seconds}s"
  # shellcheck disable=SC2086
  # Crashes and out-of-memory inputs go to build/fuzz/, not the source tree.
  "build/fuzz/fuzz/$fuzzer" -max_total_time="$seconds" -print_final_stats=1 \
    -artifact_prefix=build/fuzz/ "$corpus" $seeds
done
