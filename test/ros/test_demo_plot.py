#!/usr/bin/env python3
"""`make demo`'s command, shortened: run_demo.py ends cleanly and leaves its CSV and plot.

Runs `rosrun msm_sim run_demo.py duration:=5 output_dir:=<temporary directory>` against the
rostest master and checks: exit code 0, no "has died" in its output, the summary with the node
count, a CSV with a header and finite rows (time, fingertip force, real-time factor) in which
the finger pressed, and a PNG file.
"""
import csv
import math
import shutil
import struct
import subprocess
import tempfile
import unittest

import rostest

DURATION = 5.0  # s: the finger touches the block 1 s after the start and presses until 3 s


def png_size(path):
    """(width, height) of a PNG file; raises ValueError when it is not one."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError("%s is not a PNG file" % path)
    return struct.unpack(">II", head[16:24])


class DemoPlot(unittest.TestCase):
    def setUp(self):
        self.directory = tempfile.mkdtemp(prefix="msm_sim_demo_plot_")

    def tearDown(self):
        shutil.rmtree(self.directory, ignore_errors=True)

    def test_demo_ends_cleanly_with_csv_and_plot(self):
        run = subprocess.run(
            ["rosrun", "msm_sim", "run_demo.py", "duration:=%g" % DURATION,
             "output_dir:=" + self.directory],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
            timeout=60)
        print(run.stdout)
        self.assertEqual(run.returncode, 0)
        self.assertNotIn("has died", run.stdout)
        self.assertIn("nodes of soft_block:", run.stdout)
        self.assertIn("mean real-time factor:", run.stdout)
        csv_path = self.directory + "/demo.csv"
        png_path = self.directory + "/demo.png"
        self.assertIn(csv_path, run.stdout)
        self.assertIn(png_path, run.stdout)

        with open(csv_path) as f:
            rows = list(csv.reader(f))
        self.assertEqual(rows[0], ["time_s", "fingertip_force_N", "real_time_factor"])
        values = [[float(v) for v in row] for row in rows[1:]]
        # Wrenches come at 30 Hz: well over half of them for the DURATION seconds.
        self.assertGreater(len(values), 15 * DURATION)
        for row in values:
            self.assertEqual(len(row), 3)
            self.assertTrue(all(math.isfinite(v) for v in row), row)
        times = [r[0] for r in values]
        self.assertEqual(times, sorted(times))
        self.assertGreater(max(r[1] for r in values), 0.5, "the finger never pressed")
        self.assertTrue(all(r[1] >= 0.0 for r in values))
        self.assertTrue(all(r[2] > 0.0 for r in values))

        width, height = png_size(png_path)
        self.assertGreater(width, 100)
        self.assertGreater(height, 100)


if __name__ == "__main__":
    rostest.rosrun("msm_sim", "test_demo_plot", DemoPlot)
