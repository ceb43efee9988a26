"""Python tooling of ohm_mirror_detector3d: labels, sweep simulator, evaluator, plots.

Importing this package needs only numpy; modules that talk to ROS import rospy
themselves, so the simulator and the metrics work without a ROS installation.
"""
import threading as _threading

# Debian 11's rospy (1.15.9) calls Thread.isAlive() in its SIGINT handler; Python 3.9 removed that
# alias of is_alive(), so every rospy node that roslaunch stops with SIGINT dies with an
# AttributeError and exit status 1 (make test-compat's demo test saw it). Our nodes import this
# package first: give them the alias back where it is missing (Python 3.8, Noetic's, still has it).
if not hasattr(_threading.Thread, 'isAlive'):
    _threading.Thread.isAlive = _threading.Thread.is_alive
