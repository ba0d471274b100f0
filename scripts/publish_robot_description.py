#!/usr/bin/env python3
"""Publishes the robot_description parameter as a latched std_msgs/String on /robot_description,
so that `rosbag record` keeps the URDF with the tf it drives (msm_replay reads it from there)."""
import rospy
from std_msgs.msg import String


def main():
    rospy.init_node("robot_description_publisher")
    publisher = rospy.Publisher("/robot_description", String, queue_size=1, latch=True)
    publisher.publish(String(data=rospy.get_param("robot_description")))
    rospy.spin()


if __name__ == "__main__":
    main()
