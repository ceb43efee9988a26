#!/usr/bin/python3
"""Publishes the hand-made EchoPair fixture on `input` at ~rate Hz, stamped with the wall time, until
killed: the input publisher that test/ros/check_publisher_restart.py kills and starts again."""
import os
import sys

import rospy
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import make_pair  # noqa: E402

from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402

if __name__ == '__main__':
    rospy.init_node('fixture_publisher', anonymous=True)
    publisher = rospy.Publisher('input', EchoPair, queue_size=2)
    rate = rospy.Rate(rospy.get_param('~rate', 10.0))
    while not rospy.is_shutdown():
        publisher.publish(make_pair(Header(frame_id='laser', stamp=rospy.Time.now())))
        rate.sleep()
