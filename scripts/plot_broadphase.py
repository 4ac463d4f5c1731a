#!/usr/bin/python3
"""Plot ms per frame against N for every structure from broadphase_bench CSV output.

    scripts/plot_broadphase.py OUT.svg RESULTS.csv [MORE.csv ...]
    scripts/plot_broadphase.py --table RESULTS.csv [MORE.csv ...]   (Markdown table to stdout)

One panel per moving fraction (100 %, 5 %), log-log axes, one line per structure. Later
CSV files override earlier ones for the same (structure, N, moving).
"""
import csv
import sys

STYLE = {
    "tree": ("#1f77b4", "-", "o"),
    "quadtree": ("#2ca02c", "-", "s"),
    "sap": ("#9467bd", "-", "^"),
    "hash": ("#8c564b", "-", "D"),
    "brute": ("#7f7f7f", "-", "x"),
    "tree-tight": ("#17becf", ":", "o"),
    "box2d": ("#d62728", "--", "v"),
    "cp-bbtree": ("#ff7f0e", "--", "<"),
    "cp-hash": ("#e377c2", "--", ">"),
}


def table(paths):
    rows = {}
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                rows[(r["structure"], int(r["n"]), int(r["moving"]))] = r
    order = list(STYLE)
    print("| N | moving | structure | ms/frame | pairs/frame | build ms | heap B/proxy "
          "| structure B/proxy | closest-hit rays/s |")
    print("| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for key in sorted(rows, key=lambda k: (k[1], -k[2], order.index(k[0]) if k[0] in order else 99)):
        r = rows[key]
        struct_bytes = float(r["struct_bytes_per_proxy"])
        print(f"| {key[1]} | {key[2]}% | {key[0]} | {float(r['frame_ms']):.3f} "
              f"| {float(r['pairs']):.0f} | {float(r['build_ms']):.1f} "
              f"| {float(r['bytes_per_proxy']):.0f} "
              f"| {'-' if struct_bytes < 0 else f'{struct_bytes:.0f}'} "
              f"| {float(r['rays_per_s']) / 1e3:.0f}k |")
    return 0


def main(argv):
    if len(argv) >= 3 and argv[1] == "--table":
        return table(argv[2:])
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    # Debian's python3-matplotlib (scripts/setup.sh bench-peers); run with /usr/bin/python3.
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = argv[1]
    rows = {}
    for path in argv[2:]:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                rows[(r["structure"], int(r["n"]), int(r["moving"]))] = float(r["frame_ms"])
    movings = sorted({m for (_, _, m) in rows}, reverse=True)
    plt.rcParams["svg.hashsalt"] = "quack"  # stable ids: the SVG diffs cleanly
    fig, axes = plt.subplots(1, len(movings), figsize=(6 * len(movings), 4.5), squeeze=False)
    for ax, moving in zip(axes[0], movings):
        names = [s for s in STYLE if any(k[0] == s and k[2] == moving for k in rows)]
        names += sorted({k[0] for k in rows if k[2] == moving} - set(names))
        for name in names:
            pts = sorted((n, ms) for (s, n, m), ms in rows.items() if s == name and m == moving)
            color, line, marker = STYLE.get(name, (None, "-", "."))
            ax.plot([p[0] for p in pts], [p[1] for p in pts], line, marker=marker, color=color,
                    label=name)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("N (boxes)")
        ax.set_ylabel("ms per frame (update + pairs)")
        ax.set_title(f"{moving}% of the boxes moving")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, metadata={"Date": None})
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
