#!/usr/bin/env python3
"""Per-query cost of the batch queries at N pairs, against a plain C++ loop over the same
pairs (quack_python_baseline) and a plain Python loop over the single-pair call.

    python3 python/bench/bench_batch.py --baseline BUILD/python/quack_python_baseline [--n N]
        [--instructions]

Run it through `scripts/python.sh bench`, which builds both in release first. The module
must be importable (PYTHONPATH). Prints a table; --json FILE also writes the figures.
With --instructions it also counts instructions per query under valgrind's callgrind
(repeatable on a busy machine, where times are not): the count of a run with the loop done
twice minus the count with it done once, over N (20,000 there, to keep valgrind quick), for
the batch call and for the C++ loop.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import quack

PENTAGON = {"type": "polygon",
            "points": [[math.cos(2 * math.pi * k / 5), math.sin(2 * math.pi * k / 5)]
                       for k in range(5)]}
CASES = [
    # (op, shape a, shape b)
    ("distance", PENTAGON, PENTAGON),
    ("distance", {"type": "circle", "radius": 0.5}, {"type": "box", "half": [1, 0.5]}),
    ("overlap", PENTAGON, PENTAGON),
    ("penetration", PENTAGON, PENTAGON),
    ("raycast", PENTAGON, None),
]


def best_of(repeats, fn):
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


CHILD = """
import sys, numpy as np, quack, json
op, a, b, data, width, times = sys.argv[1:7]
rows = np.fromfile(data).reshape(-1, int(width))
a = quack.shape(json.loads(a))
b = quack.shape(json.loads(b))
pa = np.ascontiguousarray(rows[:, :3])
rest = np.ascontiguousarray(rows[:, 3:])
for _ in range(int(times)):
    if op == "raycast":
        quack.raycast_many(a, pa, rest)
    else:
        getattr(quack, op + "_many")(a, pa, b, rest)
"""


def callgrind(command, tmp):
    """Instructions the command executes (valgrind --tool=callgrind)."""
    out = os.path.join(tmp, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out] + command,
                   capture_output=True, check=True)
    with open(out) as f:
        for line in f:
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise RuntimeError("no instruction count in " + out)


def instructions_per_query(args, op, a_json, b_json, data, n, tmp):
    width = "7" if op == "raycast" else "6"
    a, b = json.dumps(a_json), json.dumps(b_json or a_json)
    batch = [callgrind([sys.executable, "-c", CHILD, op, a, b, data, width, str(k)], tmp)
             for k in (1, 2)]
    cpp = [callgrind([args.baseline, op, a, b, data, str(k), "inloop"], tmp) for k in (1, 2)]
    return (batch[1] - batch[0]) / n, (cpp[1] - cpp[0]) / n


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, help="the quack_python_baseline program")
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", help="also write the figures here")
    parser.add_argument("--instructions", action="store_true",
                        help="also count instructions per query with callgrind")
    args = parser.parse_args()
    if args.instructions and shutil.which("valgrind") is None:
        parser.error("--instructions needs valgrind (Debian package valgrind)")
    rng = np.random.default_rng(20)
    n = args.n
    # Centres within 4 m of each other: about a third of the pentagon pairs overlap.
    poses_a = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-2, 2, n),
                               rng.uniform(-math.pi, math.pi, n)])
    poses_b = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-2, 2, n),
                               rng.uniform(-math.pi, math.pi, n)])
    rays = np.column_stack([rng.uniform(-4, 4, n), rng.uniform(-4, 4, n),
                            rng.uniform(-8, 8, n), rng.uniform(-8, 8, n)])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for op, a_json, b_json in CASES:
            a = quack.shape(a_json)
            b = quack.shape(b_json) if b_json else None
            data = os.path.join(tmp, "pairs.bin")
            if op == "raycast":
                np.ascontiguousarray(np.hstack([poses_a, rays])).tofile(data)
                batch = lambda: quack.raycast_many(a, poses_a, rays)  # noqa: E731
                pa_list = [tuple(p) for p in poses_a]
                ray_list = [(tuple(r[:2]), tuple(r[2:])) for r in rays]

                def loop():
                    for i in range(n):
                        quack.raycast(a, pa_list[i], ray_list[i][0], ray_list[i][1])
            else:
                np.ascontiguousarray(np.hstack([poses_a, poses_b])).tofile(data)
                many = getattr(quack, op + "_many")
                single = getattr(quack, op)
                batch = lambda: many(a, poses_a, b, poses_b)  # noqa: E731
                pa_list = [tuple(p) for p in poses_a]
                pb_list = [tuple(p) for p in poses_b]

                def loop():
                    for i in range(n):
                        single(a, pa_list[i], b, pb_list[i])
            out = subprocess.run([args.baseline, op, json.dumps(a_json),
                                  json.dumps(b_json or a_json), data, str(args.repeats)],
                                 capture_output=True, text=True, check=True)
            cpp = json.loads(out.stdout)
            batch_ns = best_of(args.repeats, batch) / n * 1e9
            loop_ns = best_of(2, loop) / n * 1e9
            if args.instructions:
                small = os.path.join(tmp, "small.bin")
                width = 7 if op == "raycast" else 6
                np.fromfile(data).reshape(-1, width)[:20_000].tofile(small)
                batch_ir, cpp_ir = instructions_per_query(args, op, a_json, b_json, small,
                                                          20_000, tmp)
            else:
                batch_ir = cpp_ir = None
            rows.append({"batch_instructions": batch_ir, "cpp_instructions": cpp_ir,
                         "op": op, "a": a_json["type"], "b": (b_json or {"type": "-"})["type"],
                         "n": n, "cpp_ns": cpp["ns_per_query"],
                         "cpp_prebuilt_ns": cpp["ns_per_query_prebuilt"],
                         "batch_ns": batch_ns, "python_loop_ns": loop_ns})
    print(f"N = {n:,} pairs, best of {args.repeats} (Python loop: best of 2); ns per query")
    header = (f"{'op':12} {'shapes':18} {'C++ loop':>9} {'(prebuilt)':>10} {'batch':>9} "
              f"{'batch/C++':>9} {'Py loop':>9} {'loop/batch':>10}")
    print(header)
    for r in rows:
        print(f"{r['op']:12} {r['a'] + '-' + r['b']:18} {r['cpp_ns']:9.1f} "
              f"{r['cpp_prebuilt_ns']:10.1f} {r['batch_ns']:9.1f} "
              f"{r['batch_ns'] / r['cpp_ns']:9.2f} {r['python_loop_ns']:9.0f} "
              f"{r['python_loop_ns'] / r['batch_ns']:10.1f}")
    if args.instructions:
        print("\ninstructions per query (callgrind, N = 20,000)")
        print(f"{'op':12} {'shapes':18} {'C++ loop':>9} {'batch':>9} {'batch/C++':>9}")
        for r in rows:
            print(f"{r['op']:12} {r['a'] + '-' + r['b']:18} {r['cpp_instructions']:9.0f} "
                  f"{r['batch_instructions']:9.0f} "
                  f"{r['batch_instructions'] / r['cpp_instructions']:9.2f}")
    print("C++ loop: a plain loop over the same rows, building each Transform from (x, y, angle)"
          " as the batch does; (prebuilt): with the Transforms made beforehand.")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
