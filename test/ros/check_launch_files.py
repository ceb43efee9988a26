#!/usr/bin/python3
"""rostest checker of launch_files.test: every pre-filter the launch files started is alive,
advertises its four outputs, subscribes to the input topic the user gave once an output is
listened to, and nothing logged an error; colour_labels is wired to the pre-filter it was given;
a launch file for a kind of sensor loads that sensor's parameter file."""
import os
import time
import unittest

import rosgraph
import rospkg
import rospy
import rostest
import yaml
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import PointCloud2

OUTPUTS = ('labelled', 'cleaned', 'objects', 'markers')


def nodes_of(state, topic):
    """The nodes publishing or subscribing `topic`. A nodelet's topics belong to its manager's
    process, so the checks accept any node: only the pre-filter uses these names."""
    return [node for name, nodes in state if name == topic for node in nodes]


class LaunchFiles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_launch_files')
        cls.errors = []
        rospy.Subscriber('/rosout_agg', Log, cls.on_log)
        cls.instances = rospy.get_param('~instances')
        cls.viewer = rospy.get_param('~viewer')
        cls.master = rosgraph.Master(rospy.get_name())
        # Listening to `labelled` makes each pre-filter subscribe to its input (lazy subscription).
        cls.listeners = [rospy.Subscriber(i['node'] + '/labelled', PointCloud2, lambda _: None)
                         for i in cls.instances]
        cls.state = cls.wait_for(cls.all_wired, timeout=45.0)
        rospy.sleep(1.0)  # errors a node logs while it starts come in on /rosout_agg a little later

    @classmethod
    def on_log(cls, message):
        if message.level >= Log.ERROR:
            cls.errors.append('%s: %s' % (message.name, message.msg))

    @classmethod
    def all_wired(cls, state):
        publishers, subscribers, _ = state
        for instance in cls.instances:
            for topic in instance['inputs']:
                if not nodes_of(subscribers, topic):
                    return False
        # colour_labels (rospy, numpy) may register after the pre-filters on a loaded machine.
        viewer = cls.viewer['node']
        return (viewer in nodes_of(subscribers, cls.viewer['input'])
                and viewer in nodes_of(publishers, cls.viewer['output']))

    @classmethod
    def wait_for(cls, condition, timeout):
        deadline = time.time() + timeout
        state = cls.master.getSystemState()
        while not condition(state) and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.2)
            state = cls.master.getSystemState()
        return state

    def test_every_prefilter_is_alive_and_advertises_its_outputs(self):
        publishers = self.state[0]
        for instance in self.instances:
            self.assertTrue(self.master.lookupNode(instance['node']), instance['node'] + ' is not running')
            for output in OUTPUTS:
                topic = instance['node'] + '/' + output
                self.assertTrue(nodes_of(publishers, topic), '%s does not advertise %s' % (instance['node'], topic))

    def test_every_prefilter_subscribes_to_the_remapped_input(self):
        subscribers = self.state[1]
        for instance in self.instances:
            for topic in instance['inputs']:
                self.assertTrue(nodes_of(subscribers, topic), '%s is not subscribed to %s' % (instance['node'], topic))

    def test_colour_labels_follows_the_given_prefilter(self):
        publishers, subscribers, _ = self.state
        node = self.viewer['node']
        self.assertIn(node, nodes_of(subscribers, self.viewer['input']))
        self.assertIn(node, nodes_of(publishers, self.viewer['output']))

    def test_each_launch_file_loads_the_parameters_of_its_sensor(self):
        launch = os.path.join(rospkg.RosPack().get_path('ohm_mirror_detector3d'), 'launch')
        checked = 0
        for instance in self.instances:
            if 'params' not in instance:
                continue
            with open(os.path.join(launch, instance['params'])) as file:
                wanted = yaml.safe_load(file)
            for name, value in wanted.items():
                if name in instance.get('set_by_arguments', []):
                    continue
                self.assertEqual(rospy.get_param(instance['node'] + '/' + name), value,
                                 '%s: %s is not that of %s' % (instance['node'], name, instance['params']))
                checked += 1
        self.assertGreater(checked, 0)

    def test_nothing_logged_an_error(self):
        self.assertEqual(self.errors, [])


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'launch_files', LaunchFiles)
