"""python3 -m msm_sim.sweep against a real dask-scheduler and two dask-worker processes on
localhost: results and errors recorded, reruns skip finished points, and a worker killed
mid-sweep leaves every point exactly once in the file."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from msm_sim import sweep

# Six points, each a static solve of about a second; poisson 0.7 is no material: an error.
GRID = """command: compression
options: {model: cubic, size: [2.0, 1.0, 1.0], spacing: 0.05, youngs: 1.0e5, density: 1100.0}
grid:
  poisson: [0.2, 0.25, 0.3, 0.35, 0.4, 0.7]
"""


def wait_for(condition, what, timeout=120.0):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError("timed out waiting for " + what)
        time.sleep(0.1)


@pytest.fixture
def cluster(tmp_path):
    """A dask-scheduler and two single-threaded dask-worker processes (no nanny: killing one
    kills the worker); yields (address, [worker processes])."""
    scheduler_file = tmp_path / "scheduler.json"
    common = ["--no-dashboard"]
    processes = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", "0",
                                   "--scheduler-file", str(scheduler_file)] + common,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        wait_for(scheduler_file.exists, "the scheduler file")
        address = json.loads(scheduler_file.read_text())["address"]
        workers = [subprocess.Popen(["dask-worker", address, "--nthreads", "1", "--no-nanny",
                                     "--name", "w%d" % i] + common,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                   for i in range(2)]
        processes += workers
        from distributed import Client
        with Client(address) as client:
            client.wait_for_workers(2, timeout=120)
        yield address, workers
    finally:
        for process in reversed(processes):
            if process.poll() is None:
                process.terminate()
                process.wait(timeout=30)


STARTED = []  # every sweep process a test started, ended by the autouse fixture below


@pytest.fixture(autouse=True)
def end_sweeps():
    yield
    while STARTED:
        process = STARTED.pop()
        if process.poll() is None:
            process.kill()
            process.communicate()


def run_sweep(grid, out, *options):
    process = subprocess.Popen([sys.executable, "-m", "msm_sim.sweep", str(grid), "--out",
                                str(out)] + list(options), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    STARTED.append(process)
    return process


def records(out):
    with open(out) as stream:
        return [json.loads(line) for line in stream]


def test_grid_is_the_product_with_bundles_and_exclusions(tmp_path):
    grid = tmp_path / "grid.yaml"
    grid.write_text("command: grasp\noptions: {youngs: 2.0e5}\ngrid:\n"
                    "  object: [{shape: sphere, radius: 0.02}, {shape: mesh, mesh: bean.obj}]\n"
                    "  friction: [0.5, 0.8]\nexclude: [{shape: sphere, friction: 0.8}]\n")
    command, points = sweep.load_grid(str(grid))
    assert command == "grasp" and len(points) == 3
    assert points[0] == {"youngs": 2.0e5, "shape": "sphere", "radius": 0.02, "friction": 0.5}
    assert points[1]["mesh"] == str(tmp_path / "bean.obj")
    grid.write_text("command: grasp\ngrid: {friction: 0.5}\n")
    with pytest.raises(ValueError, match="needs a list"):
        sweep.load_grid(str(grid))


def test_sweep_records_results_errors_and_skips_finished_points(cluster, tmp_path):
    address, _ = cluster
    grid, out = tmp_path / "grid.yaml", tmp_path / "results.jsonl"
    grid.write_text(GRID)
    run = run_sweep(grid, out, "--scheduler", address)
    stdout, stderr = run.communicate(timeout=300)
    assert run.returncode == 0, stderr
    found = records(out)
    assert len(found) == 6
    errors = [r for r in found if "error" in r]
    assert len(errors) == 1 and errors[0]["options"]["poisson"] == 0.7
    assert errors[0]["error"].startswith("msm_lab: error: ")
    for record in found:
        assert record["worker"].startswith("tcp://127.0.0.1:") and record["seconds"] > 0.0
    assert all(r["result"]["command"] == "compression" for r in found if "result" in r)
    assert "[6/6]" in stdout
    again = run_sweep(grid, out, "--scheduler", address)
    stdout, stderr = again.communicate(timeout=300)
    assert again.returncode == 0, stderr
    assert "6 already in" in stdout and "0 to run" in stdout
    assert len(records(out)) == 6


def test_worker_killed_mid_sweep_leaves_every_point_once(cluster, tmp_path):
    address, workers = cluster
    grid, out = tmp_path / "grid.yaml", tmp_path / "results.jsonl"
    grid.write_text(GRID)
    run = run_sweep(grid, out, "--scheduler", address)
    from distributed import Client
    with Client(address) as client:
        doomed = next(a for a, w in client.scheduler_info()["workers"].items()
                      if w["name"] == "w1")
        # Killed while it runs a point, once the sweep has written its first record.
        wait_for(lambda: out.exists() and out.read_text().count("\n") >= 1
                 and client.processing(workers=[doomed])[doomed], "w1 running a later point")
        os.kill(workers[1].pid, signal.SIGKILL)
    stdout, stderr = run.communicate(timeout=300)
    assert run.returncode == 0, stderr
    found = records(out)
    poissons = sorted(r["options"]["poisson"] for r in found)
    assert poissons == [0.2, 0.25, 0.3, 0.35, 0.4, 0.7]
    assert sum("result" in r for r in found) == 5


def test_local_cluster(tmp_path):
    grid, out = tmp_path / "grid.yaml", tmp_path / "results.jsonl"
    grid.write_text("command: compression\noptions: {model: cubic, size: [2.0, 1.0, 1.0], "
                    "spacing: 0.125, youngs: 1.0e5}\ngrid:\n  poisson: [0.25, 0.3]\n")
    run = run_sweep(grid, out, "--workers", "1")
    stdout, stderr = run.communicate(timeout=300)
    assert run.returncode == 0, stderr
    assert sorted(r["options"]["poisson"] for r in records(out)) == [0.25, 0.3]
    assert len({r["worker"] for r in records(out)}) == 1
