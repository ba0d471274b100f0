#!/usr/bin/env python3
"""The grasp demo's outcome (test/ros/grasp.test): the object rose at least 4.9 cm of the 5 cm
lift, and while held the pads' vertical friction forces (the simulation's per-link wrenches)
sum to the object's weight m g within 5 %, m from the simulation's diagnostics.
"""
import json
import math
import unittest

import rospy
import rostest
from std_msgs.msg import String


class GraspDemo(unittest.TestCase):
    def test_lifts_the_object_and_the_pads_carry_its_weight(self):
        rospy.init_node("test_grasp_demo")
        message = rospy.wait_for_message("/grasp_gripper/summary", String, timeout=280.0)
        summary = json.loads(message.data)
        for key in ("squeeze_force", "rise", "slip", "vertical_friction", "weight",
                    "real_time_factor"):
            self.assertTrue(math.isfinite(summary[key]), "%s: %s" % (key, summary))
        self.assertGreaterEqual(summary["rise"], 0.049, summary)
        self.assertLessEqual(summary["slip"], 1e-3, summary)
        self.assertAlmostEqual(summary["vertical_friction"], summary["weight"],
                               delta=0.05 * summary["weight"], msg=summary)
        self.assertGreater(summary["squeeze_force"], 0.0, summary)
        self.assertGreater(summary["real_time_factor"], 0.0, summary)


if __name__ == "__main__":
    rostest.rosrun("msm_sim", "test_grasp_demo", GraspDemo)
