#!/usr/bin/env python3
"""Closes the grasp demo's parallel gripper (urdf/parallel_gripper.urdf) on the object, holds it,
lifts it and holds it up, through sensor_msgs/JointState in ROS time (the simulation's /clock),
then prints a summary, writes grasp.csv and grasp.png and publishes the summary as JSON on
~summary (latched).

Each finger approaches at ~approach_speed until its pad's wrench (~links/<pad>/wrench of the
simulation) shows contact, then squeezes at ~squeeze_speed until it presses ~squeeze_force
(N), and holds that position; after ~hold_time the lift rises ~lift (m) over ~lift_time (s)
with a quintic profile, and holds for ~final_hold. The summary, over the last second of the
final hold: squeeze force per pad, the object's rise (its frame on /tf, the centre of mass), its
slip (the lift minus the rise), the pads' vertical friction against the weight m g (the mass
from the simulation's diagnostics) and the mean real-time factor. SI units throughout.
"""
import json
import math
import os
import signal

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

JOINTS = ["lift", "left_finger_joint", "right_finger_joint"]
CONTACT_FORCE = 0.02  # N: a pad's normal force that counts as touching


def quintic(s):
    """0 -> 1 with zero velocity and acceleration at both ends."""
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


class Finger:
    """One finger's squeeze: approach, squeeze to the force, hold the position."""

    def __init__(self, pad, side, approach_speed, squeeze_speed, target, limit):
        self.pad, self.side = pad, side
        self.approach_speed, self.squeeze_speed = approach_speed, squeeze_speed
        self.target, self.limit = target, limit
        self.position, self.force, self.done = 0.0, 0.0, False
        self.vertical = 0.0  # N, the pad's vertical force from the object (down is negative)

    def on_wrench(self, message):
        # The object pushes the left pad along -x, the right one along +x.
        self.force = self.side * message.wrench.force.x
        self.vertical = message.wrench.force.z

    def advance(self, dt):
        if self.done:
            return
        if self.force >= self.target:
            self.done = True
            return
        speed = self.squeeze_speed if self.force > CONTACT_FORCE else self.approach_speed
        self.position = min(self.position + speed * dt, self.limit)


class Grasp:
    def __init__(self):
        p = lambda name, default: rospy.get_param("~" + name, default)
        self.object = p("object", "bean")
        self.frame = p("world_frame", "world")
        self.lift, self.lift_time = p("lift", 0.05), p("lift_time", 2.0)
        self.hold_time, self.final_hold = p("hold_time", 1.5), p("final_hold", 1.5)
        self.start_delay, self.close_timeout = p("start_delay", 0.5), p("close_timeout", 5.0)
        self.output_dir = os.path.expanduser(p("output_dir", "") or os.path.join(
            os.environ.get("ROS_HOME", os.path.expanduser("~/.ros")), "msm_sim_grasp"))
        sim = p("simulation", "/msm_sim")
        force, limit = p("squeeze_force", 2.0), p("finger_travel", 0.025)
        approach, squeeze = p("approach_speed", 0.005), p("squeeze_speed", 0.001)
        self.fingers = [Finger("left_pad", -1.0, approach, squeeze, force, limit),
                        Finger("right_pad", 1.0, approach, squeeze, force, limit)]
        for finger in self.fingers:
            rospy.Subscriber(sim + "/links/" + finger.pad + "/wrench", WrenchStamped,
                             finger.on_wrench, queue_size=10)
        self.mass, self.rtf = None, []
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=10)
        self.height = float("nan")  # the object's frame (its centre of mass) above the world
        rospy.Subscriber("/tf", TFMessage, self.on_tf, queue_size=100)
        self.joints = rospy.Publisher("joint_states", JointState, queue_size=10)
        self.summary = rospy.Publisher("~summary", String, queue_size=1, latch=True)
        self.rows = []

    def on_diagnostics(self, message):
        for status in message.status:
            for entry in status.values:
                if entry.key == "mass " + self.object + " [kg]":
                    self.mass = float(entry.value)
                elif entry.key == "real-time factor" and float(entry.value) > 0.0:
                    self.rtf.append(float(entry.value))

    def publish(self, lift):
        message = JointState()
        message.header.stamp = rospy.Time.now()
        message.name = JOINTS
        message.position = [lift] + [f.position for f in self.fingers]
        self.joints.publish(message)

    def on_tf(self, message):
        # The simulation publishes each object's frame directly in the world frame.
        for transform in message.transforms:
            if transform.child_frame_id == self.object and \
                    transform.header.frame_id == self.frame:
                self.height = transform.transform.translation.z

    def object_height(self):
        return self.height

    def record(self, t, lift):
        z = self.object_height()
        left, right = self.fingers
        self.rows.append((t, lift, z, left.force, right.force, left.vertical + right.vertical))

    def run(self):
        rate = rospy.Rate(rospy.get_param("~rate", 100.0))
        while not rospy.is_shutdown() and rospy.Time.now().is_zero():
            rospy.sleep(0.01)  # the simulation's clock not running yet
        start = rospy.Time.now()
        dt = 1.0 / rospy.get_param("~rate", 100.0)
        phase_start, lift_start, z0 = None, None, None
        while not rospy.is_shutdown():
            t = (rospy.Time.now() - start).to_sec()
            lift = 0.0
            if t > self.start_delay and phase_start is None:
                for finger in self.fingers:
                    finger.advance(dt)
                if all(f.done for f in self.fingers) or t > self.start_delay + self.close_timeout:
                    phase_start = t
            if phase_start is not None and t > phase_start + self.hold_time:
                if lift_start is None:
                    lift_start, z0 = t, self.object_height()
                lift = self.lift * quintic((t - lift_start) / self.lift_time)
                if t > lift_start + self.lift_time + self.final_hold:
                    self.hold()
                    return self.finish(z0)
            self.publish(lift)
            self.record(t, lift)
            rate.sleep()

    def hold(self):
        """Publishes the final pose (lifted, fingers where they stopped) from a timer until
        shutdown, while the summary is written and the launch ends: the links' tf stays fresh,
        so the simulation keeps their contacts and does not warn of stale links."""
        period = rospy.Duration(1.0 / rospy.get_param("~rate", 100.0))
        self.holder = rospy.Timer(period, lambda event: self.publish(self.lift))

    def finish(self, z0):
        held = [r for r in self.rows if r[0] >= self.rows[-1][0] - 1.0]
        mean = lambda values: sum(values) / len(values) if values else float("nan")
        rise = mean([r[2] for r in held]) - z0
        weight = (self.mass or float("nan")) * 9.81
        summary = {
            "squeeze_force": mean([0.5 * (r[3] + r[4]) for r in held]),
            "rise": rise,
            "slip": self.lift - rise,
            "vertical_friction": -mean([r[5] for r in held]),
            "weight": weight,
            "real_time_factor": mean(self.rtf),
        }
        self.summary.publish(String(data=json.dumps(summary)))
        rospy.loginfo(
            "grasp: squeeze %.3f N per pad, rise %.1f mm of %.1f, slip %.2f mm, pads' vertical "
            "friction %.4f N against m g %.4f N, real-time factor %.2f",
            summary["squeeze_force"], 1e3 * rise, 1e3 * self.lift, 1e3 * summary["slip"],
            summary["vertical_friction"], weight, summary["real_time_factor"])
        self.write(summary)
        return summary

    def write(self, summary):
        os.makedirs(self.output_dir, exist_ok=True)
        with open(os.path.join(self.output_dir, "grasp.csv"), "w") as out:
            out.write("t_s,lift_m,object_z_m,left_force_N,right_force_N,vertical_friction_N\n")
            for row in self.rows:
                out.write(",".join("%.6g" % v for v in row) + "\n")
        with open(os.path.join(self.output_dir, "grasp.json"), "w") as out:
            json.dump(summary, out, indent=1)
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            rospy.logwarn("grasp: matplotlib missing; no plot")
            return
        t = [r[0] for r in self.rows]
        z0 = next((r[2] for r in self.rows if not math.isnan(r[2])), 0.0)
        figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
        top.plot(t, [1e3 * r[1] for r in self.rows], label="lift (joint)")
        top.plot(t, [1e3 * (r[2] - z0) for r in self.rows], label="object rise (centre of mass)")
        top.set_ylabel("mm")
        top.legend()
        bottom.plot(t, [r[3] for r in self.rows], label="left pad normal force")
        bottom.plot(t, [r[4] for r in self.rows], label="right pad normal force")
        bottom.plot(t, [-r[5] for r in self.rows], label="pads' vertical friction")
        if not math.isnan(summary["weight"]):
            bottom.axhline(summary["weight"], color="grey", linestyle="--", label="m g")
        bottom.set_xlabel("simulated time (s)")
        bottom.set_ylabel("N")
        bottom.legend()
        figure.tight_layout()
        figure.savefig(os.path.join(self.output_dir, "grasp.png"), dpi=100)
        rospy.loginfo("grasp: wrote %s", os.path.join(self.output_dir, "grasp.png"))


def end_launch():
    """Ends the roslaunch that started this node as Ctrl-C would: every node stops and roslaunch
    exits 0, without the alarm a `required` node's exit raises. False (and nothing done) when the
    parent process is not roslaunch (rosrun, rostest)."""
    parent = os.getppid()
    try:
        with open("/proc/%d/cmdline" % parent, "rb") as f:
            command = f.read().split(b"\0")
    except OSError:
        return False
    if not any(os.path.basename(part) == b"roslaunch" for part in command[:2]):
        return False
    os.kill(parent, signal.SIGINT)
    return True


def main():
    rospy.init_node("grasp_gripper")
    grasp = Grasp()
    grasp.run()
    rospy.sleep(1.0)  # let the latched summary reach its subscribers
    if rospy.get_param("~end_launch", False) and end_launch():
        rospy.spin()  # holding the pose (Grasp.hold) while roslaunch stops the nodes


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
