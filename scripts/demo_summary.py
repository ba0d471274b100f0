#!/usr/bin/env python3
"""Prints a short summary of the demo after ~duration seconds and ends the launch.

Peak force on the fingertip (~links/fingertip/wrench), mean real-time factor and the final
energy of the object (/diagnostics).
"""
import math
import sys

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped


class Summary:
    def __init__(self):
        self.peak = 0.0
        self.rtf = []
        self.energy = {}
        self.simulated = 0.0
        rospy.Subscriber("/msm_sim/links/fingertip/wrench", WrenchStamped, self.on_wrench)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics)

    def on_wrench(self, message):
        f = message.wrench.force
        self.peak = max(self.peak, math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z))

    def on_diagnostics(self, message):
        for status in message.status:
            for entry in status.values:
                if entry.key == "real-time factor":
                    self.rtf.append(float(entry.value))
                elif entry.key == "simulated time [s]":
                    self.simulated = float(entry.value)
                elif entry.key.startswith("energy "):
                    name = entry.key[len("energy "):].replace(" [J]", "")
                    self.energy[name] = float(entry.value)


def main():
    rospy.init_node("demo_summary")
    duration = rospy.get_param("~duration", 10.0)
    summary = Summary()
    end = rospy.get_time() + duration
    while not rospy.is_shutdown() and rospy.get_time() < end:
        rospy.sleep(0.1)
    rtf = sum(summary.rtf[1:]) / max(len(summary.rtf) - 1, 1)
    print("msm_sim demo summary after %.1f s of simulation:" % summary.simulated)
    print("  peak contact force on the fingertip: %.3f N" % summary.peak)
    print("  mean real-time factor:               %.2f" % rtf)
    for name, energy in sorted(summary.energy.items()):
        print("  final energy of %-20s %.5f J" % (name + ":", energy))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
