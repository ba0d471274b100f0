"""Runs a lab command over a grid of options on Dask distributed (docs/python.md).

    python3 -m msm_sim.sweep GRID.yaml --out results.jsonl [--scheduler ADDRESS] [--workers N]

GRID.yaml names the command, the options every point shares and, per varied option, its list of
values; the points are the product of those lists. A value that is a mapping sets several
options at once (a shape with its dimensions), and `exclude` drops the points that match any of
its partial option sets:

    command: compression
    options: {model: cubic, size: [2.0, 1.0, 1.0], youngs: 1.0e5}
    grid:
      spacing: [0.125, 0.1]
      material: [{poisson: 0.25}, {poisson: 0.45, surface_dispersion: 0.5}]
    exclude: [{spacing: 0.1, poisson: 0.45}]

Each point is one task: without --scheduler on a local cluster of N single-threaded worker
processes (default: one per core), with it on an existing cluster (`dask-scheduler`, and
`dask-worker ADDRESS --nthreads 1` wherever msm_sim is importable). Each result is appended to
the JSON-lines file as soon as its task finishes: the command, the point's options, the result
dict or the error message, the worker and the seconds. Points already in the file (with a
result or an error) are not run again; a failed point records its error and the sweep goes on;
Dask reruns the task of a worker lost mid-task, and a point is written once, when its task
finishes. Progress: a tqdm bar on a terminal, one line per point otherwise.
"""
import argparse
import itertools
import json
import logging
import os
import re
import socket
import sys
import time

import yaml


class GridLoader(yaml.SafeLoader):
    """YAML as the grid files mean it: 1e5 and 2.5e-3 are numbers (YAML 1.1, which PyYAML
    reads, takes an exponent without a sign or a dot for a string)."""


GridLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"))


def load_grid(path):
    """(command, points): the grid file's command and its points, each a dict of options."""
    with open(path) as stream:
        grid = yaml.load(stream, Loader=GridLoader)
    if not isinstance(grid, dict) or "command" not in grid:
        raise ValueError("%s: a grid file needs a command" % path)
    unknown = set(grid) - {"command", "options", "grid", "exclude"}
    if unknown:
        raise ValueError("%s: unknown keys %s" % (path, ", ".join(sorted(unknown))))
    fixed = grid.get("options") or {}
    axes = []
    for name, values in (grid.get("grid") or {}).items():
        if not isinstance(values, list) or not values:
            raise ValueError("%s: grid %s needs a list of values" % (path, name))
        axes.append([v if isinstance(v, dict) else {name: v} for v in values])
    exclude = grid.get("exclude") or []
    base = os.path.dirname(os.path.abspath(path))
    points = []
    for combination in itertools.product(*axes):
        point = dict(fixed)
        for part in combination:
            point.update(part)
        if any(all(point.get(k) == v for k, v in rule.items()) for rule in exclude):
            continue
        # A mesh named relative to the grid file is found wherever the sweep is started.
        if "mesh" in point and not os.path.isabs(point["mesh"]):
            point["mesh"] = os.path.normpath(os.path.join(base, point["mesh"]))
        points.append(point)
    return grid["command"], points


def point_key(command, options):
    """What identifies a point in the results file."""
    return json.dumps([command, options], sort_keys=True)


def run_point(command, options):
    """One point, on a worker: the record the results file gets."""
    from msm_sim import lab
    start = time.perf_counter()
    record = {"command": command, "options": options}
    try:
        record["result"] = lab.run(command, **options)
    except (ValueError, RuntimeError) as error:
        record["error"] = str(error)
    try:
        from distributed import get_worker
        record["worker"] = get_worker().address
    except ValueError:  # not on a Dask worker
        record["worker"] = "%s:%d" % (socket.gethostname(), os.getpid())
    record["seconds"] = time.perf_counter() - start
    return record


def finished_points(path):
    """The keys of the points the results file already has a result or an error for."""
    done = set()
    if not os.path.exists(path):
        return done
    with open(path) as stream:
        for line in stream:
            try:
                record = json.loads(line)
            except ValueError:  # a line cut short by a killed sweep: run the point again
                continue
            if "result" in record or "error" in record:
                done.add(point_key(record["command"], record["options"]))
    return done


def pending_points(command, points, out):
    """The grid's points not yet in the results file, each once."""
    done = finished_points(out)
    pending, seen = [], set()
    for point in points:
        key = point_key(command, point)
        if key not in done and key not in seen:
            seen.add(key)
            pending.append(point)
    return pending


def connect(scheduler, workers):
    """(client, cluster): a Dask client on the cluster at `scheduler` (cluster None), else on
    a new local cluster of single-threaded worker processes."""
    from distributed import Client, LocalCluster
    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                           processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


class Progress:
    """A tqdm bar on a terminal; otherwise one line per finished point on stdout."""

    def __init__(self, total):
        self.total, self.count = total, 0
        self.bar = None
        if sys.stderr.isatty():
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit="point")

    def update(self, record):
        self.count += 1
        if self.bar is not None:
            self.bar.update(1)
            return
        outcome = "error: " + record["error"] if "error" in record else "ok"
        print("[%d/%d] %s %s" % (self.count, self.total, json.dumps(record["options"]), outcome),
              flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def sweep(command, points, out, client):
    """Runs the points on the client's cluster, appending each record to `out` as it finishes;
    returns (results, errors)."""
    from distributed import as_completed
    futures = {client.submit(run_point, command, point, pure=False): point for point in points}
    progress = Progress(len(futures))
    counts = [0, 0]
    with open(out, "a") as stream:
        for future in as_completed(futures):
            try:
                record = future.result()
            except Exception as error:  # the task itself failed: e.g. its workers kept dying
                record = {"command": command, "options": futures[future],
                          "error": "%s: %s" % (type(error).__name__, error),
                          "worker": None, "seconds": None}
            future.release()
            stream.write(json.dumps(record) + "\n")
            stream.flush()
            counts["error" in record] += 1
            progress.update(record)
    progress.close()
    return counts[0], counts[1]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m msm_sim.sweep", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("grid", help="the grid file (YAML)")
    parser.add_argument("--out", required=True, help="the JSON-lines results file (appended)")
    parser.add_argument("--scheduler", help="address of an existing Dask scheduler")
    parser.add_argument("--workers", type=int, help="local workers (default: one per core)")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be >= 1")
    try:
        command, points = load_grid(args.grid)
    except (OSError, ValueError, yaml.YAMLError) as error:
        parser.error(str(error).splitlines()[0])
    pending = pending_points(command, points, args.out)
    print("%s: %d points, %d already in %s, %d to run" % (
        command, len(points), len(points) - len(pending), args.out, len(pending)), flush=True)
    if not pending:
        return 0
    client, cluster = connect(args.scheduler, args.workers)
    try:
        results, errors = sweep(command, pending, args.out, client)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    print("%d results, %d errors, in %s" % (results, errors, args.out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
