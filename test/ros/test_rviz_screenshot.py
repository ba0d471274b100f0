#!/usr/bin/env python3
"""Screenshot of rviz running the demo on display :97: the soft block must be drawn.

The block is drawn in strain colours (a light silicone tone unstrained, red or blue strained),
rviz's background is dark grey with grey grid lines: count the central pixels that are neither.
"""
import subprocess
import time
import unittest

import rospy
import rostest


class RvizScreenshot(unittest.TestCase):
    def test_block_is_drawn(self):
        rospy.init_node("test_rviz_screenshot")
        # rviz starts in a few seconds; the finger presses 1 to 3 s after the demo starts.
        time.sleep(12.0)
        shot = "/tmp/msm_sim_rviz_screenshot.png"
        subprocess.run(["import", "-display", ":97", "-window", "root", shot], check=True,
                       timeout=30)
        share = float(subprocess.run(
            ["convert", shot, "-crop", "400x300+200+150", "+repage", "-fx",
             "(abs(r-g)>0.08 || abs(g-b)>0.08 || (r>0.6 && g>0.6 && b>0.6)) ? 1 : 0",
             "-format", "%[fx:mean]", "info:"],
            check=True, capture_output=True, text=True, timeout=30).stdout)
        print("share of central pixels showing the block: %.3f (%s)" % (share, shot))
        self.assertGreater(share, 0.05, "the soft block is not drawn (see %s)" % shot)


if __name__ == "__main__":
    rostest.rosrun("msm_sim", "test_rviz_screenshot", RvizScreenshot)
