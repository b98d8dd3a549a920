#!/usr/bin/env python3
"""Compare the rows of two report.json files on their quality metrics (timings ignored).

Usage: tools/compare_report_rows.py BEFORE/report.json AFTER/report.json [--filter TECHNIQUE]
Rows are matched by (scene, technique, params label); prints every row whose quality metrics differs, and a summary. Exit status 1 when any row differs or is missing.
"""
import json
import sys

KEYS = ("rmse", "mean_abs", "p99_abs", "penumbra_rmse", "misclassified", "leak_fraction", "leak_mean_excess")


def rows(path, only):
    data = json.load(open(path))
    out = {}
    for r in data["rows"]:
        if only and r.get("technique") != only:
            continue
        key = (r.get("scene"), r.get("technique"), json.dumps(r.get("params"), sort_keys=True))
        out[str(key)] = {k: r.get(k) for k in KEYS} | {"failed": r.get("failed", False)}
    return out


def main(argv):
    only = None
    if "--filter" in argv:
        i = argv.index("--filter")
        only = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    a, b = rows(argv[0], only), rows(argv[1], only)
    diff = 0
    for k in sorted(set(a) | set(b)):
        if k not in a or k not in b:
            print("only in", "after" if k in b else "before", k)
            diff += 1
        elif a[k] != b[k]:
            print(k, "before", a[k], "after", b[k])
            diff += 1
    print(f"{len(a)} rows before, {len(b)} after, {diff} differ")
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
