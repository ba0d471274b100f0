#!/usr/bin/env python3
"""Runs `msm_lab grasp` over the grasp issue's grid and prints a Markdown table.

Shapes: sphere 5 cm, cylinder 4 x 6 cm lying across the pads, ellipsoid 6 x 4 x 3 cm and the
bean mesh (meshes/soft_bean.obj scaled to 5 cm); nu 0.3 and 0.49; spacings 2.5, 3 and 5 mm;
mu 0.5 and 0.8; both integrators; Q 1.5 (must hold) and 0.6 (must drop). E 259 kPa, rho 1070.
Usage: grasp_grid.py MSM_LAB [--quick] [--spacings A ...] [--integrators NAME ...]
[--shapes NAME ...] (--quick: spacings 5 and 3 mm, explicit only; the others: these only).
"""
import itertools
import json
import os
import subprocess
import sys

PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = {
    "sphere": ["--shape", "sphere", "--radius", "0.025"],
    "cylinder": ["--shape", "cylinder", "--radius", "0.02", "--length", "0.06"],
    "ellipsoid": ["--shape", "ellipsoid", "--size", "0.06", "0.04", "0.03"],
    "bean": ["--shape", "mesh", "--mesh", os.path.join(PACKAGE, "meshes", "soft_bean.obj"),
             "--scale", "0.42"],
}


def option(name):
    """The values after `name` on the command line, up to the next option; [] if absent."""
    if name not in sys.argv:
        return []
    values = []
    for value in sys.argv[sys.argv.index(name) + 1:]:
        if value.startswith("--"):
            break
        values.append(value)
    return values


def main():
    lab = sys.argv[1]
    quick = "--quick" in sys.argv
    spacings = option("--spacings") or (["0.005", "0.003"] if quick else
                                         ["0.005", "0.003", "0.0025"])
    integrators = option("--integrators") or (["explicit"] if quick else
                                              ["explicit", "implicit"])
    print("| shape | nu | spacing | mu | integrator | nodes | Q 1.5: rise mm, slip mm | "
          "Q 0.6: rise mm | Q 30: max speed m/s | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    failures = 0
    shapes = option("--shapes") or list(SHAPES)
    # The quickest rows first: a long run's table fills from coarse to fine.
    for integrator, spacing, shape, nu, mu in itertools.product(
            integrators, spacings, shapes, ["0.3", "0.49"], ["0.5", "0.8"]):
        results = {}
        for q in ["1.5", "0.6", "30"]:
            if q == "30" and mu != "0.8":
                continue
            command = [lab, "grasp"] + SHAPES[shape] + [
                "--spacing", spacing, "--youngs", "259e3", "--poisson", nu, "--density", "1070",
                "--friction", mu, "--force-ratio", q, "--integrator", integrator, "--json"]
            if nu == "0.49":
                command += ["--surface-dispersion", "0.25"]
            run = subprocess.run(command, capture_output=True, text=True)
            results[q] = json.loads(run.stdout) if run.returncode == 0 else {"error": run.stderr}
        hold, drop = results["1.5"], results["0.6"]
        squeeze = results.get("30")
        ok = hold.get("held") is True and drop.get("rise", 1.0) < 0.025 and (
            squeeze is None or (squeeze.get("held") and squeeze.get("max_node_speed", 9) < 1.0))
        failures += not ok
        print("| %s | %s | %g mm | %s | %s | %s | %.2f, %.3f | %.2f | %s | %s |" % (
            shape, nu, 1e3 * float(spacing), mu, integrator, hold.get("nodes", "-"),
            1e3 * hold.get("rise", float("nan")), 1e3 * hold.get("slip", float("nan")),
            1e3 * drop.get("rise", float("nan")),
            "%.3f" % squeeze["max_node_speed"] if squeeze and "max_node_speed" in squeeze else "-",
            "ok" if ok else "FAIL"), flush=True)
    print("\n%d of the grid's rows failed" % failures)


if __name__ == "__main__":
    main()
