#!/usr/bin/env python3
"""Stepping from Python against stepping in C++: the scene of test/python/scene.py (a cube on
the ground, a sphere pressing down) at 2.5 mm (4,096 nodes), 1,000 steps of 1 ms, stepped by
msm_world_reference (the C++ World alone) and by msm_sim.World from Python, alternately, ROUNDS
times each; prints the best time of each and their ratio, measured in this one run. The issue's
target: Python within 3 % of C++.
Usage: python_step_benchmark.py MSM_WORLD_REFERENCE [--rounds N] (the workspace sourced)
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test",
                                "python"))
from scene import build_world  # noqa: E402

SPACING, STEPS = 0.0025, 1000


def cpp_seconds(reference, integrator):
    with tempfile.TemporaryDirectory() as directory:
        run = subprocess.run([reference, integrator, repr(SPACING), str(STEPS),
                              os.path.join(directory, "positions.bin")],
                             check=True, capture_output=True, text=True)
    return float(run.stdout)


def python_seconds(integrator):
    world = build_world(integrator, SPACING)
    start = time.perf_counter()
    for _ in range(STEPS):
        world.step(1e-3)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("reference")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--integrator", default="explicit")
    args = parser.parse_args()
    nodes = build_world(args.integrator, SPACING).positions(0).shape[0]
    cpp, python = [], []
    for _ in range(args.rounds):
        cpp.append(cpp_seconds(args.reference, args.integrator))
        python.append(python_seconds(args.integrator))
    print("%d nodes, %d steps, %s: C++ %.3f s, Python %.3f s (best of %d): Python / C++ = %.4f"
          % (nodes, STEPS, args.integrator, min(cpp), min(python), args.rounds,
             min(python) / min(cpp)))


if __name__ == "__main__":
    main()
