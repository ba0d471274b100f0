#!/usr/bin/env python3
"""Scripted joint states for the demo finger (urdf/finger_gantry.urdf).

Presses the fingertip into the top of the default soft block at slide_x = ~start_x, holds,
drags it across along +x (from -1.5 cm to +1.5 cm, centred on the block), holds and lifts,
publishing sensor_msgs/JointState for slide_x and slide_z at ~rate Hz in ROS time. Parameters
(private, SI units): ~start_delay, ~start_x, ~press_depth (below first contact), ~press_time,
~hold_time, ~drag_distance, ~drag_time, ~contact_z (slide_z at first contact), ~rate.
"""
import rospy
from sensor_msgs.msg import JointState


def smooth(s):
    """Smoothstep: 0 -> 1 with zero velocity at both ends."""
    s = min(max(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def main():
    rospy.init_node("demo_finger")
    delay = rospy.get_param("~start_delay", 1.0)
    start_x = rospy.get_param("~start_x", -0.015)
    depth = rospy.get_param("~press_depth", 0.008)
    press = rospy.get_param("~press_time", 2.0)
    hold = rospy.get_param("~hold_time", 1.0)
    drag = rospy.get_param("~drag_distance", 0.03)
    drag_time = rospy.get_param("~drag_time", 3.0)
    contact_z = rospy.get_param("~contact_z", -0.09)   # the tip touches the block's top face
    up_z = contact_z + 0.02
    rate = rospy.Rate(rospy.get_param("~rate", 100.0))
    publisher = rospy.Publisher("joint_states", JointState, queue_size=10)
    start = rospy.Time.now()
    while not rospy.is_shutdown():
        if start.is_zero():  # simulated clock not running yet
            start = rospy.Time.now()
            rate.sleep()
            continue
        t = (rospy.Time.now() - start).to_sec() - delay
        x, z = start_x, up_z
        if t > 0.0:
            z = up_z - (up_z - (contact_z - depth)) * smooth(t / press)
        if t > press + hold:
            x = start_x + drag * smooth((t - press - hold) / drag_time)
        if t > press + 2.0 * hold + drag_time:
            z = (contact_z - depth) + (up_z - (contact_z - depth)) * smooth(
                (t - press - 2.0 * hold - drag_time) / press)
        message = JointState()
        message.header.stamp = rospy.Time.now()
        message.name = ["slide_x", "slide_z"]
        message.position = [x, z]
        publisher.publish(message)
        rate.sleep()


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
