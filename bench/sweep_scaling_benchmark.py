#!/usr/bin/env python3
"""The sweep on 2 local workers against 1: the same CPU-bound grid (8 static compressions of a
block, each about a second on one core) run by msm_sim.sweep on a local Dask cluster of one
single-threaded worker, then of two; prints both times and the speed-up, measured in this one
run (cluster start-up excluded). The issue's target: at least 1.8x on 2 workers, which needs
two idle cores.
Usage: sweep_scaling_benchmark.py (the workspace sourced)
"""
import logging
import os
import tempfile
import time

from distributed import Client, LocalCluster

from msm_sim import sweep

COMMAND = "compression"
POINTS = [{"model": "cubic", "size": [2.0, 1.0, 1.0], "spacing": 0.05, "youngs": 1.0e5,
           "poisson": p}
          for p in (0.2, 0.22, 0.24, 0.26, 0.28, 0.3, 0.32, 0.34)]


def sweep_seconds(workers, directory):
    out = os.path.join(directory, "results-%d.jsonl" % workers)
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        client.submit(sweep.run_point, COMMAND, POINTS[0], pure=False).result()  # warm up
        start = time.perf_counter()
        results, errors = sweep.sweep(COMMAND, POINTS, out, client)
        seconds = time.perf_counter() - start
    assert (results, errors) == (len(POINTS), 0)
    return seconds


def main():
    with tempfile.TemporaryDirectory() as directory:
        one = sweep_seconds(1, directory)
        two = sweep_seconds(2, directory)
    print("%d points: 1 worker %.2f s, 2 workers %.2f s: speed-up %.2fx"
          % (len(POINTS), one, two, one / two))


if __name__ == "__main__":
    main()
