#!/usr/bin/env python3
"""rostest: msm_sim_node's dynamic_reconfigure servers (README "Runtime tuning").

`dynparam set` on an object's E recalibrates its springs (the diagnostics' mean spring stiffness
doubles with E at fixed nu), a refused value (nu = 0.5) leaves the material and the springs
unchanged and is sent back, and the world's publish rate and pacing change the publication.
"""
import subprocess
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from dynamic_reconfigure.client import Client

OBJECT = "/msm_sim/reconfigure/objects/block"
WORLD = "/msm_sim/reconfigure/world"
STIFFNESS = "mean spring stiffness block [N/m]"


class RuntimeTuning(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_runtime_tuning")
        cls.messages = []  # (wall time, {key: value})
        cls.stamps = []  # the node's stamps of the same messages
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls.on_diagnostics)

    @classmethod
    def on_diagnostics(cls, message):
        for status in message.status:
            values = {entry.key: entry.value for entry in status.values}
            if STIFFNESS in values:
                cls.messages.append((time.time(), values))
                cls.stamps.append(message.header.stamp.to_sec())

    def fresh(self, key, timeout=20.0):
        """The value of `key` in the first diagnostics published after this call."""
        start = time.time()
        while time.time() - start < timeout:
            later = [values for stamp, values in self.messages if stamp > start + 0.05]
            if later:
                return float(later[0][key])
            time.sleep(0.02)
        self.fail("no diagnostics with %r within %.0f s" % (key, timeout))

    def dynparam(self, *arguments):
        return subprocess.run(["rosrun", "dynamic_reconfigure", "dynparam"] + list(arguments),
                              capture_output=True, text=True, timeout=60)

    def test_youngs_recalibrates_and_a_refused_value_changes_nothing(self):
        client = Client(OBJECT, timeout=30)
        before = client.get_configuration(timeout=10)
        self.assertAlmostEqual(before["youngs"], 5e4)  # test/ros/push.yaml
        self.assertAlmostEqual(before["poisson"], 0.3)
        k0 = self.fresh(STIFFNESS)
        run = self.dynparam("set", OBJECT, "youngs", "100000")
        self.assertEqual(run.returncode, 0, run.stderr)
        k1 = self.fresh(STIFFNESS)
        # Springs scale with E at fixed nu (the diagnostics print 6 digits).
        self.assertAlmostEqual(k1 / k0, 2.0, delta=2e-5)

        after = client.update_configuration({"poisson": 0.5})  # nu must be < 0.5: refused
        self.assertAlmostEqual(after["poisson"], 0.3)
        self.assertAlmostEqual(after["youngs"], 1e5)
        self.assertEqual(self.fresh(STIFFNESS), k1)
        run = self.dynparam("set", OBJECT, "youngs", "0")  # E must be > 0: refused
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertAlmostEqual(client.get_configuration(timeout=10)["youngs"], 1e5)
        self.assertEqual(self.fresh(STIFFNESS), k1)

    def test_publish_rate_and_pacing(self):
        """At 10 Hz, paced: the node stamps its publications 0.1 s apart. The median interval of
        its own stamps, not a count of arrivals by the wall clock, so that a machine another
        build keeps busy (late ticks, late deliveries) does not fail it."""
        client = Client(WORLD, timeout=30)
        self.assertFalse(client.get_configuration(timeout=10)["real_time"])  # push.yaml
        client.update_configuration({"publish_rate": 10.0, "real_time": True})
        time.sleep(0.5)
        first = len(self.stamps)
        time.sleep(3.0)
        stamps = self.stamps[first:]
        self.assertGreaterEqual(len(stamps), 6, "fewer than 6 publications in 3 s at 10 Hz")
        intervals = sorted(b - a for a, b in zip(stamps, stamps[1:]))
        self.assertAlmostEqual(intervals[len(intervals) // 2], 0.1, delta=0.02)
        client.update_configuration({"publish_rate": 50.0, "real_time": False})


if __name__ == "__main__":
    rostest.rosrun("msm_sim", "test_runtime_tuning", RuntimeTuning)
