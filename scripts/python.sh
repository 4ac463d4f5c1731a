#!/usr/bin/env bash
# The Python module `quack` (docs/python.md), from a fresh Debian machine. Each mode first
# installs the Debian packages it needs (scripts/setup.sh build python: as root it installs
# them, otherwise it names the command), then builds the module with the release preset
# (build/release).
#   scripts/python.sh install            # make `python3 -c "import quack"` work anywhere:
#                                        #   root: /usr/local/lib/python3.X/dist-packages
#                                        #   user: ~/.local/lib/python3.X/site-packages
#   scripts/python.sh install --prefix D # put it in directory D instead (add D to PYTHONPATH)
#   scripts/python.sh uninstall [--prefix D]
#   scripts/python.sh bench [--n N] [--instructions]  # batch queries vs a C++ loop vs a
#                                        #   Python loop (--instructions: callgrind counts too)
#   scripts/python.sh bench-state [--bodies N ...]    # World.body_state() vs the get_*
#                                        #   copies, set_body_state vs the set_* calls
# The module is built for Debian's /usr/bin/python3 (whose numpy and pybind11 Debian ships);
# QUACK_PYTHON=/path/to/python3 chooses another interpreter that has numpy.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
shift || true
python=${QUACK_PYTHON:-/usr/bin/python3}
[ -x "$python" ] || python=$(command -v python3)
say() { printf 'python.sh: %s\n' "$*" >&2; }
usage() { sed -n '2,16p' "$0" >&2; exit 2; }

# The release preset's build (build/release), so that CI's release build is reused.
build() {
  local bench=$1
  cmake --preset release -DQUACK_BUILD_PYTHON=ON -DPython3_EXECUTABLE="$python" \
    ${bench:+-DQUACK_BUILD_BENCHMARKS=ON} >/dev/null
  local targets=quack_python
  [ -n "$bench" ] && targets="quack_python quack_python_baseline"
  # shellcheck disable=SC2086
  cmake --build --preset release --target $targets
}

# Where the module goes: --prefix D, else the interpreter's own place for local packages.
target_dir() {
  if [ "${1:-}" = --prefix ]; then
    [ -n "${2:-}" ] || usage
    echo "$2"
  elif [ "$(id -u)" -eq 0 ]; then
    "$python" -c 'import sys; print(f"/usr/local/lib/python3.{sys.version_info.minor}/dist-packages")'
  else
    "$python" -m site --user-site
  fi
}

case "$mode" in
  install)
    dir=$(target_dir "$@")
    scripts/setup.sh build python
    build ""
    mkdir -p "$dir"
    cmake --install build/release --component python --prefix "$dir" >/dev/null
    say "installed $(ls "$dir"/quack.*.so) for $python"
    # The proof: imported from elsewhere, with nothing but the interpreter's own path (and
    # the prefix, when one was given).
    ( cd / && if [ "${1:-}" = --prefix ]; then export PYTHONPATH="$dir"; fi
      "$python" -c 'import quack; print("python.sh: import quack works:", quack.__file__)' )
    ;;
  uninstall)
    dir=$(target_dir "$@")
    rm -fv "$dir"/quack.*.so
    ;;
  bench)
    scripts/setup.sh build bench python
    build ON
    PYTHONPATH="$PWD/build/release/python" "$python" python/bench/bench_batch.py \
      --baseline build/release/python/quack_python_baseline --json build/release/bench_batch.json \
      "$@"
    ;;
  bench-state)
    scripts/setup.sh build python
    build ""
    PYTHONPATH="$PWD/build/release/python" "$python" python/bench/bench_state.py \
      --json build/release/bench_state.json "$@"
    ;;
  *) usage ;;
esac
