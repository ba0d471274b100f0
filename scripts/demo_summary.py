#!/usr/bin/env python3
"""Prints a short summary of the demo after ~duration seconds and plots it.

Node count, peak force on the fingertip (~links/fingertip/wrench), mean real-time factor, mean
step time and the final energy of each object (/diagnostics). Writes ~output_dir/demo.csv
(time, fingertip force, real-time factor; one row per fingertip wrench from the first
diagnostics on) and ~output_dir/demo.png (both against time) and prints their paths.
~output_dir defaults to $ROS_HOME/msm_sim_demo (~/.ros/msm_sim_demo). Exits 0 once done;
scripts/run_demo.py then ends the launch.
"""
import csv
import math
import os
import sys

import rospkg
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped

CSV_HEADER = ["time_s", "fingertip_force_N", "real_time_factor"]


class Summary:
    def __init__(self):
        self.peak = 0.0
        self.rtf = []
        self.step_ms = []
        self.energy = {}
        self.nodes = {}
        self.simulated = 0.0
        self.rows = []  # [time since start (s), |fingertip force| (N), latest real-time factor]
        self.start = rospy.get_time()
        rospy.Subscriber("/msm_sim/links/fingertip/wrench", WrenchStamped, self.on_wrench)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics)

    def on_wrench(self, message):
        f = message.wrench.force
        force = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
        self.peak = max(self.peak, force)
        if self.rtf:  # the real-time factor is known from the first diagnostics on
            self.rows.append([rospy.get_time() - self.start, force, self.rtf[-1]])

    def on_diagnostics(self, message):
        for status in message.status:
            for entry in status.values:
                if entry.key == "real-time factor":
                    self.rtf.append(float(entry.value))
                elif entry.key == "step time [ms]":
                    self.step_ms.append(float(entry.value))
                elif entry.key == "simulated time [s]":
                    self.simulated = float(entry.value)
                elif entry.key.startswith("nodes "):
                    self.nodes[entry.key[len("nodes "):]] = int(entry.value)
                elif entry.key.startswith("energy "):
                    name = entry.key[len("energy "):].replace(" [J]", "")
                    self.energy[name] = float(entry.value)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(CSV_HEADER)
        for time, force, rtf in rows:
            writer.writerow(["%.4f" % time, "%.6f" % force, "%.4f" % rtf])


def plot(path, rows, title):
    import matplotlib
    matplotlib.use("Agg")  # headless: no display needed
    import matplotlib.pyplot as plt

    time = [r[0] for r in rows]
    fig, (force_axis, rtf_axis) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.2))
    force_axis.plot(time, [r[1] for r in rows], color="tab:blue")
    force_axis.set_ylabel("fingertip force |F| (N)")
    force_axis.grid(True, color="0.9")
    force_axis.set_title(title)
    rtf_axis.plot(time, [r[2] for r in rows], color="tab:green")
    rtf_axis.axhline(1.0, color="tab:red", linewidth=0.8, linestyle="--")
    rtf_axis.set_ylabel("real-time factor")
    rtf_axis.set_xlabel("time (s)")
    rtf_axis.set_ylim(bottom=0.0)
    rtf_axis.grid(True, color="0.9")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def mean_after_first(values):
    """The first report covers start-up (building the model, the first tf): left out."""
    return sum(values[1:]) / max(len(values) - 1, 1)


def report(summary, time_step, csv_path, png_path):
    rtf = mean_after_first(summary.rtf)
    step_ms = mean_after_first(summary.step_ms)
    print("msm_sim demo summary after %.1f s of simulation:" % summary.simulated)
    for name, nodes in sorted(summary.nodes.items()):
        print("  nodes of %-27s %d" % (name + ":", nodes))
    print("  peak contact force on the fingertip: %.3f N" % summary.peak)
    print("  mean real-time factor:               %.2f" % rtf)
    if step_ms > 0.0:  # paced to the clock, the factor stays near 1; the steps show the margin
        print("  mean step time:                      %.3f ms per %.3g ms step (the steps alone:"
              " %.2f x real time)" % (step_ms, 1e3 * time_step, 1e3 * time_step / step_ms))
    for name, energy in sorted(summary.energy.items()):
        print("  final energy of %-20s %.5f J" % (name + ":", energy))
    print("  force and real-time factor: %s" % csv_path)
    print("  plot:                       %s" % png_path)
    sys.stdout.flush()


def main():
    rospy.init_node("demo_summary")
    duration = rospy.get_param("~duration", 10.0)
    default_dir = os.path.join(rospkg.get_ros_home(), "msm_sim_demo")
    output_dir = os.path.expanduser(rospy.get_param("~output_dir", "") or default_dir)
    summary = Summary()
    end = rospy.get_time() + duration
    while not rospy.is_shutdown() and rospy.get_time() < end:
        rospy.sleep(0.1)
    if rospy.is_shutdown():
        return 1
    os.makedirs(output_dir, exist_ok=True)
    csv_path = os.path.join(output_dir, "demo.csv")
    png_path = os.path.join(output_dir, "demo.png")
    rows = list(summary.rows)
    write_csv(csv_path, rows)
    nodes = sum(summary.nodes.values())
    plot(png_path, rows, "msm_sim demo: %d nodes, mean real-time factor %.2f" %
         (nodes, mean_after_first(summary.rtf)))
    report(summary, rospy.get_param("/msm_sim/world/time_step", 0.001), csv_path, png_path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
