#!/usr/bin/python3
"""rostest checker: the multi-sweep post-filter through the nodelet (post_filter.test).

The window pane of scene pane_in_wall returns a surface echo only near the perpendicular, so one
sweep sees a patch of it. Three sweeps from places 0.25 m apart along the wall, each with its pose
on /tf, must build one map object in the fixed frame (map, through the static map <- odom) that
keeps its id, grows from sweep to sweep and stays glass, published on ~map_objects and
~map_evidence. A sweep whose pose tf does not have is processed single-sweep (its outputs come)
and the map stays as it was. ~save_map writes the map; ~load_map of a corrupt file answers with the
problem and empties the map; loading the saved file brings it back. Two more nodelets on the same
input start from map files (parameter map_file): a good one keeps its object (id 7) and hands out
ids from its next_id on, a corrupt one starts with an empty map.
"""
import os
import tempfile
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped

from ohm_mirror_detector3d.msg import EchoPair, ObjectMapEvidence, ReflectiveObjectArray
from ohm_mirror_detector3d.srv import MapFile
from ohm_mirror_detector3d.ros_io import sweep_to_messages
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d.scanner import RotatingHokuyo
from ohm_mirror_detector3d.scene import Pose
from ohm_mirror_detector3d.simulate import simulate_sweep

MAP_FROM_ODOM = np.array([1.0, 0.5, 0.0])  # the static transform of post_filter.test
SHIFTS = (0.0, 0.25, 0.5)                  # the three places along the wall (y), from the scene's


def quaternion_z(yaw):
    return (0.0, 0.0, np.sin(yaw / 2), np.cos(yaw / 2))


class PostFilter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.outputs = {}
        cls.subscribers = [rospy.Subscriber(node + '/' + topic, kind, cls.on_output, callback_args=name,
                                            queue_size=10)
                           for node, prefix in (('prefilter', ''), ('prefilter_known', 'known_'),
                                                ('prefilter_corrupt', 'corrupt_'))
                           for topic, kind in (('objects', ReflectiveObjectArray),
                                               ('map_objects', ReflectiveObjectArray),
                                               ('map_evidence', ObjectMapEvidence))
                           for name in (prefix + topic,)]
        cls.publisher = rospy.Publisher('prefilter/input', EchoPair, queue_size=1)
        cls.tf = tf2_ros.TransformBroadcaster()
        scene = scenes.get('pane_in_wall')
        cls.pane = next(o for o in scene.objects() if o.name == 'pane')
        start = scene.scanner_pose
        cls.poses = [Pose((start.position[0], start.position[1] + dy, start.position[2]), (0.0, 0.0, 0.1 * k))
                     for k, dy in enumerate(SHIFTS)]
        cls.sweeps = [simulate_sweep(scene, RotatingHokuyo(scans=200, range_noise=0.01), seed=k, pose=pose)
                      for k, pose in enumerate(cls.poses)]
        deadline = rospy.Time.now() + rospy.Duration(30)
        while cls.publisher.get_num_connections() < 3 and rospy.Time.now() < deadline:
            rospy.sleep(0.1)
        # Each sweep in order: with its pose (map answers) and one without (no map answer).
        cls.answers = [cls.send(sweep, pose) for sweep, pose in zip(cls.sweeps, cls.poses)]
        cls.without_pose = cls.send(cls.sweeps[0], None, wait_for=('objects',))

    @classmethod
    def on_output(cls, msg, topic):
        cls.outputs.setdefault(msg.header.stamp, {})[topic] = msg

    @classmethod
    def send(cls, sweep, pose, wait_for=('objects', 'map_objects', 'map_evidence', 'known_map_objects',
                                         'corrupt_map_objects'), timeout=60.0):
        stamp = rospy.Time.now()
        if pose is not None:
            t = TransformStamped()
            t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, 'odom', 'laser'
            t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = pose.position
            r = t.transform.rotation
            r.x, r.y, r.z, r.w = quaternion_z(pose.rpy[2])
            cls.tf.sendTransform(t)
            rospy.sleep(0.3)  # the listener has it before the sweep comes
        else:
            stamp = stamp - rospy.Duration(60.0)  # before anything tf holds: no pose will come
        cls.publisher.publish(sweep_to_messages(sweep, stamp)['echo_pair'])
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while not all(t in cls.outputs.get(stamp, {}) for t in wait_for) and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        rospy.sleep(0.5)  # anything else of that stamp would have come by now
        return cls.outputs.pop(stamp, {})

    def test_one_map_object_keeps_its_id_grows_and_stays_glass_in_the_fixed_frame(self):
        widths, ids = [], []
        for k, answer in enumerate(self.answers):
            self.assertIn('map_objects', answer, 'sweep %d: no ~map_objects' % k)
            objects = answer['map_objects']
            self.assertEqual(objects.header.frame_id, 'map')
            self.assertEqual(len(objects.objects), 1, [o.id for o in objects.objects])
            o = objects.objects[0]
            self.assertEqual(o.type, o.TYPE_GLASS)
            ids.append(o.id)
            widths.append(o.width)
            corners = np.array([[c.x, c.y, c.z] for c in o.corners])
            # On the pane's plane x = 5 of the world (odom), 1 m further in map.
            np.testing.assert_allclose(corners[:, 0], 5.0 + MAP_FROM_ODOM[0], atol=0.05)
            evidence = answer['map_evidence']
            self.assertEqual(list(evidence.ids), [o.id])
            self.assertEqual(list(evidence.sweeps_seen), [k + 1])
            self.assertLess(evidence.mirror_log_odds[0], 0.0)
        self.assertEqual(len(set(ids)), 1, ids)
        self.assertGreater(widths[1], widths[0] + 0.1, widths)
        self.assertGreater(widths[2], widths[1] + 0.1, widths)
        self.assertLessEqual(widths[2], self.pane.width + 0.05, widths)

    def test_a_sweep_without_its_pose_is_processed_single_sweep(self):
        self.assertIn('objects', self.without_pose)
        self.assertNotIn('map_objects', self.without_pose)
        # Its own objects only (single-sweep): the patch, not the map's grown pane.
        widths = [o.width for o in self.without_pose['objects'].objects]
        self.assertEqual(len(widths), 1, widths)
        self.assertLess(widths[0], self.answers[-1]['map_objects'].objects[0].width - 0.1)

    def test_a_map_file_is_loaded_at_start_and_a_corrupt_one_gives_an_empty_map(self):
        first = self.answers[0]
        known = first['known_map_objects']
        self.assertEqual([o.id for o in known.objects], [7, 8])
        self.assertEqual(known.objects[0].type, known.objects[0].TYPE_GLASS)
        self.assertAlmostEqual(known.objects[0].width, 0.1, places=4)
        self.assertEqual(list(first['known_map_evidence'].sweeps_seen), [4, 1])
        corrupt = first['corrupt_map_objects']
        self.assertEqual([o.id for o in corrupt.objects], [0])

    def test_the_map_is_saved_and_loaded_and_a_corrupt_file_empties_it(self):
        save = rospy.ServiceProxy('prefilter/save_map', MapFile)
        load = rospy.ServiceProxy('prefilter/load_map', MapFile)
        rospy.wait_for_service('prefilter/save_map', 10)
        directory = tempfile.mkdtemp()
        path = os.path.join(directory, 'map.yaml')
        answer = save(path)
        self.assertTrue(answer.success, answer.message)
        with open(path) as f:
            text = f.read()
        self.assertIn('fixed_frame: map', text)
        corrupt = os.path.join(directory, 'corrupt.yaml')
        with open(corrupt, 'w') as f:
            f.write(text[:len(text) // 2] + '\n  - [unclosed\n')
        answer = load(corrupt)
        self.assertFalse(answer.success)
        self.assertIn(corrupt, answer.message)
        empty = self.send(self.sweeps[2], self.poses[2])
        self.assertEqual(len(empty['map_objects'].objects), 1)  # only this sweep's patch again
        self.assertEqual(empty['map_evidence'].sweeps_seen[0], 1)
        answer = load(path)
        self.assertTrue(answer.success, answer.message)
        self.assertIn('1 objects loaded', answer.message)
        again = self.send(self.sweeps[2], self.poses[2])
        self.assertEqual(again['map_objects'].objects[0].id, self.answers[0]['map_objects'].objects[0].id)
        self.assertEqual(again['map_evidence'].sweeps_seen[0], 4)


if __name__ == '__main__':
    rospy.init_node('check_post_filter')
    rostest.rosrun('ohm_mirror_detector3d', 'post_filter', PostFilter)
