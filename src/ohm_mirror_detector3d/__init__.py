"""Python tooling of ohm_mirror_detector3d: labels, sweep simulator, evaluator, plots.

Importing this package needs only numpy; modules that talk to ROS import rospy
themselves, so the simulator and the metrics work without a ROS installation.
"""
