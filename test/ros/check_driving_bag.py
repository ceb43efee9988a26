#!/usr/bin/python3
"""rostest checker of a driving sensor's bag: writes a bag of three sweeps of hesai_qt64 on the wall
mirror's pass (sensor_path.scene_path) with /tf, replays it with `rosbag play` into the running
pre-filter, and checks, for every sweep, that the pre-filter's outputs come in the sweep's frame and
stamp, that tf2 (a TransformListener fed by the replayed /tf) gives odom <- that frame at that stamp
equal to the simulated pose, and that the cleaned cloud taken into odom with it lies in the room, as
it would not without the pose (the sensor drives along the middle of the room)."""
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import PointCloud2

from ohm_mirror_detector3d import ros_io
from ohm_mirror_detector3d import scanner as scanners
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d.dual_return_cloud import dual_return_messages
from ohm_mirror_detector3d.scan_sequence import quaternion_matrix
from ohm_mirror_detector3d.sensor_path import FIXED_FRAME, scene_path
from ohm_mirror_detector3d.simulate import SweepSimulator

SCENE, SWEEPS, FRAME, START, PERIOD = 'wall_mirror', 3, 'lidar', 100.0, 0.5
ROOM = np.array([[0.0, 0.0, 0.0], [5.0, 4.0, 2.6]])   # wall_mirror's room


class DrivingBag(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_driving_bag')
        cls.dir = tempfile.mkdtemp(prefix='driving_bag_')
        cls.path = scene_path(SCENE, SWEEPS)
        scene = scenes.get(SCENE)
        simulator = SweepSimulator(scene, scanners.preset('hesai_qt64'))
        sweeps = [simulator.sweep(seed=k, pose=pose) for k, pose in enumerate(cls.path.poses)]
        bag = os.path.join(cls.dir, 'drive.bag')
        cls.stamps = ros_io.write_sweeps_bag(bag, sweeps, START, PERIOD, FRAME,
                                             to_messages=lambda s, t, f: dual_return_messages(s, t, f),
                                             sensor_path=cls.path)
        cls.buffer = tf2_ros.Buffer(rospy.Duration(1000.0))
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        cls.cleaned = {}
        sub = rospy.Subscriber('/prefilter/cleaned', PointCloud2, lambda m: cls.cleaned.setdefault(m.header.stamp, m),
                               queue_size=10, buff_size=2 ** 26)
        deadline = rospy.Time.now() + rospy.Duration(30.0)
        while sub.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.1)
        # --delay: the pre-filter subscribes to /lidar/points only once its output is listened to and
        # the bag's publisher is advertised; give the connection time before the first sweep.
        subprocess.check_call(['rosbag', 'play', '--quiet', '--delay', '3', bag, '/points:=/lidar/points'])
        deadline = rospy.Time.now() + rospy.Duration(60.0)
        while len(cls.cleaned) < SWEEPS and rospy.Time.now() < deadline:
            rospy.sleep(0.1)
        sub.unregister()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_every_replayed_sweep_is_cleaned_in_its_frame_and_stamp(self):
        self.assertEqual(sorted(self.cleaned), self.stamps)
        for msg in self.cleaned.values():
            self.assertEqual(msg.header.frame_id, FRAME)

    def test_tf_gives_the_simulated_pose_at_every_sweeps_stamp(self):
        for k, stamp in enumerate(self.stamps):
            t = self.buffer.lookup_transform(FIXED_FRAME, FRAME, stamp, rospy.Duration(5.0)).transform
            np.testing.assert_allclose([t.translation.x, t.translation.y, t.translation.z],
                                       self.path.poses[k].position, atol=1e-6)
            np.testing.assert_allclose(quaternion_matrix((t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)),
                                       self.path.poses[k].rotation(), atol=1e-6)

    def test_cleaned_cloud_taken_into_odom_with_tf_lies_in_the_room(self):
        for stamp in self.stamps:
            cloud = ros_io.cloud_to_array(self.cleaned[stamp], ['x', 'y', 'z'])
            points = np.stack([cloud['x'], cloud['y'], cloud['z']], axis=1).astype(float)
            t = self.buffer.lookup_transform(FIXED_FRAME, FRAME, stamp, rospy.Duration(5.0)).transform
            rotation = quaternion_matrix((t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w))
            world = points @ rotation.T + [t.translation.x, t.translation.y, t.translation.z]
            inside = np.all((world >= ROOM[0] - 0.1) & (world <= ROOM[1] + 0.1), axis=1)
            self.assertGreater(inside.mean(), 0.99, 'cleaned points in the room, in odom')
            raw = np.all((points >= ROOM[0] - 0.1) & (points <= ROOM[1] + 0.1), axis=1)
            self.assertLess(raw.mean(), 0.9, 'without the pose the cloud would not fit the room')


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'driving_bag', DrivingBag)
