#!/usr/bin/python3
"""input_types.test: no silent no-output. Pre-filter nodes started here (their log read from their
output) get publishers of other types on their input topics, clouds that never pair and parameters
they do not use; each says so, naming the type and the input_mode that reads it, the stamp
difference, the parameter. The diagnostics name the topics really subscribed."""
import os
import subprocess
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import MultiEchoLaserScan, PointCloud2, PointField
from std_msgs.msg import Header

from ohm_mirror_detector3d.msg import EchoPair

TIMEOUT = 30.0


class Node:
    """A pre-filter node of its own name, its output (log) collected line by line."""

    def __init__(self, name, *params):
        self.name = '/' + name
        self.lines = []
        # rosconsole block-buffers INFO lines (stdout) into a pipe unless told otherwise.
        environment = dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED='1')
        self.process = subprocess.Popen(['rosrun', 'ohm_mirror_detector3d', 'ohm_mirror_prefilter3d', '__name:=' + name]
                                        + list(params), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                        env=environment)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()
        # Listening to an output makes it subscribe to its input (lazy subscription).
        self.listener = rospy.Subscriber(self.name + '/labelled', PointCloud2, lambda _: None)

    def _read(self):
        for line in self.process.stdout:
            self.lines.append(line.rstrip())

    def wait_for(self, *texts, while_waiting=None):
        """The first line of the log holding every one of `texts` (None after TIMEOUT)."""
        deadline = time.time() + TIMEOUT
        while time.time() < deadline and not rospy.is_shutdown():
            for line in list(self.lines):
                if all(text in line for text in texts):
                    return line
            if while_waiting:
                while_waiting()
            time.sleep(0.2)
        return None

    def stop(self):
        self.listener.unregister()
        self.process.terminate()
        self.process.wait(10)


def cloud(stamp, fields=('x', 'y', 'z'), frame='laser'):
    message = PointCloud2(header=Header(stamp=stamp, frame_id=frame), height=1, width=1, is_dense=True,
                          is_bigendian=False)
    message.fields = [PointField(name=name, offset=4 * k, datatype=PointField.FLOAT32, count=1)
                      for k, name in enumerate(fields)]
    message.point_step = 4 * len(fields)
    message.row_step = message.point_step
    message.data = bytes(message.point_step)
    return message


class InputTypes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_input_types')

    def run_node(self, name, *params):
        node = Node(name, *params)
        self.addCleanup(node.stop)
        return node

    def test_a_publisher_of_another_type_on_a_typed_input_is_named_with_the_mode_that_reads_it(self):
        node = self.run_node('forced_pair', '_input_mode:=pair')
        diagnostics = []
        rospy.Subscriber('/diagnostics', DiagnosticArray, diagnostics.append)
        scans = rospy.Publisher('/forced_pair/input', MultiEchoLaserScan, queue_size=1)
        line = node.wait_for('dropping messages on /forced_pair/input: its publisher sends '
                             'sensor_msgs/MultiEchoLaserScan, but ohm_mirror_detector3d/EchoPair is read here',
                             'input_mode multi_echo_scan reads it, with sweep_frame')
        self.assertIsNotNone(line, '\n'.join(node.lines))
        deadline = time.time() + TIMEOUT
        errors = []
        while not errors and time.time() < deadline:
            errors = [status for array in list(diagnostics) for status in array.status
                      if 'forced_pair' in status.name and status.level == DiagnosticStatus.ERROR]
            time.sleep(0.2)
        self.assertTrue(errors, 'no ERROR on /diagnostics')
        self.assertIn('no input can arrive: /forced_pair/input: its publisher sends sensor_msgs/MultiEchoLaserScan',
                      errors[-1].message)
        self.assertEqual(errors[-1].hardware_id, '/forced_pair/input')
        scans.unregister()

    def test_without_input_mode_another_type_is_named_with_the_mode_that_reads_it(self):
        node = self.run_node('by_type', '_sub_input_scan:=/lidar/points')
        self.assertIsNotNone(node.wait_for('pre-filter ready: input_mode not set, input /lidar/points'),
                             '\n'.join(node.lines))
        clouds = rospy.Publisher('/lidar/points', PointCloud2, queue_size=1)
        lidar = cloud(rospy.Time(5), ('x', 'y', 'z', 'return', 'ring'))
        line = node.wait_for('dropping message on /lidar/points: its type sensor_msgs/PointCloud2 is not read without '
                             'input_mode', 'it has a return and a ring field: input_mode dual_return reads one cloud',
                             while_waiting=lambda: clouds.publish(lidar))
        self.assertIsNotNone(line, '\n'.join(node.lines))
        clouds.unregister()

    def test_an_echo_pair_is_read_without_input_mode_and_its_mode_is_said(self):
        node = self.run_node('pair_by_type', '_outlierFilter_minNeighbors:=1', '_outlierFilter_searchRadius:=100.0')
        pairs = rospy.Publisher('/pair_by_type/input', EchoPair, queue_size=1)
        header = Header(stamp=rospy.Time(7), frame_id='laser')
        pair = EchoPair(header=header, echo1=cloud(header.stamp), echo2=cloud(header.stamp))
        line = node.wait_for('input /pair_by_type/input: ohm_mirror_detector3d/EchoPair', 'read as input_mode pair',
                             while_waiting=lambda: pairs.publish(pair))
        self.assertIsNotNone(line, '\n'.join(node.lines))
        pairs.unregister()

    def test_clouds_that_never_pair_are_counted_with_their_stamp_difference(self):
        node = self.run_node('unpaired', '_input_mode:=two_topics')
        ready = node.wait_for('pre-filter ready: input_mode two_topics, input /unpaired/echo1 '
                              '(sensor_msgs/PointCloud2) and /unpaired/echo2 (sensor_msgs/PointCloud2)')
        self.assertIsNotNone(ready, '\n'.join(node.lines))
        echo1 = rospy.Publisher('/unpaired/echo1', PointCloud2, queue_size=5)
        echo2 = rospy.Publisher('/unpaired/echo2', PointCloud2, queue_size=5)
        stamp = [100.0]

        def publish():
            # A driver that stamps its second return 25 ms after the first.
            echo1.publish(cloud(rospy.Time.from_sec(stamp[0])))
            echo2.publish(cloud(rospy.Time.from_sec(stamp[0] + 0.025)))
            stamp[0] += 1.0

        line = node.wait_for('dropping sweep on /unpaired/echo1 + /unpaired/echo2: cloud on',
                             'with the same stamp (its stamp', 'the nearest there is 0.025 s',
                             'approximate_sync pairs clouds that far apart', 'unpaired so far',
                             while_waiting=publish)
        self.assertIsNotNone(line, '\n'.join(node.lines))
        echo1.unregister()
        echo2.unregister()

    def test_every_parameter_it_does_not_use_gets_one_warning(self):
        node = self.run_node('unused', '_source_frame:=laser', '_outlierFilter_minNeighbours:=5',
                             '_sweep_frame:=base_link', '_r:=0.2')
        self.assertIsNotNone(node.wait_for('pre-filter ready'), '\n'.join(node.lines))
        warnings = [line for line in node.lines if 'parameter /unused/' in line]
        self.assertEqual(len(warnings), 3, '\n'.join(node.lines))
        self.assertIn('/unused/source_frame is no parameter of the pre-filter and is ignored (a typo, or a name of '
                      'the original node that has no meaning here)', '\n'.join(warnings))
        self.assertIn('/unused/outlierFilter_minNeighbours is no parameter of the pre-filter and is ignored (did you '
                      'mean outlierFilter_minNeighbors?)', '\n'.join(warnings))
        self.assertIn('/unused/sweep_frame is not used with input_mode not set', '\n'.join(warnings))


if __name__ == '__main__':
    rostest.rosrun('ohm_mirror_detector3d', 'input_types', InputTypes)
