#!/usr/bin/env python3
"""Prints the grasp grid's Markdown table from the sweep's results (config/sweeps/grasp.yaml):
one row per shape, nu, spacing, mu and integrator, with its verdict. Held at Q 1.5, dropped at
Q 0.6 (rise < 25 mm), and at Q 30 still held with no node faster than 1 m/s.
Usage: grasp_table.py RESULTS.jsonl
"""
import json
import sys

NAN = float("nan")


def rows(path):
    """{(shape, nu, spacing, mu, integrator): {Q: result dict or {"error": ...}}}"""
    table = {}
    with open(path) as stream:
        for line in stream:
            record = json.loads(line)
            o = record["options"]
            key = (o["shape"], o["poisson"], o["spacing"], o["friction"], o["integrator"])
            table.setdefault(key, {})[o["force_ratio"]] = record.get("result", record)
    return table


def main():
    table = rows(sys.argv[1])
    print("| shape | nu | spacing | mu | integrator | nodes | Q 1.5: rise mm, slip mm | "
          "Q 0.6: rise mm | Q 30: max speed m/s | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    failures = 0
    for (shape, nu, spacing, mu, integrator), runs in sorted(table.items()):
        hold, drop, squeeze = runs.get(1.5, {}), runs.get(0.6, {}), runs.get(30.0)
        ok = hold.get("held") is True and drop.get("rise", 1.0) < 0.025 and (
            squeeze is None or (squeeze.get("held") and squeeze.get("max_node_speed", 9) < 1.0))
        failures += not ok
        print("| %s | %s | %g mm | %s | %s | %s | %.2f, %.3f | %.2f | %s | %s |" % (
            shape, nu, 1e3 * spacing, mu, integrator, hold.get("nodes", "-"),
            1e3 * hold.get("rise", NAN), 1e3 * hold.get("slip", NAN),
            1e3 * drop.get("rise", NAN),
            "%.3f" % squeeze["max_node_speed"] if squeeze and "max_node_speed" in squeeze else "-",
            "ok" if ok else "FAIL"))
    print("\n%d of the grid's %d rows failed" % (failures, len(table)))


if __name__ == "__main__":
    main()
