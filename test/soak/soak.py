#!/usr/bin/python3
"""Soak test (`make soak`): ~sweeps sweeps, each answered before the next is sent, through the
pre-filter nodelet; the nodelet manager's resident memory (VmRSS) is sampled from /proc and must
stay flat: within 1 MB between sweep 100 (buffers warmed up) and the last. Every answer must hold
every input point. Prints the RSS samples as a table."""
import math
import os
import sys
import time
import unittest
import xmlrpc.client

import numpy as np
import rosgraph
import rospy
import rostest
from sensor_msgs.msg import PointCloud2, PointField
from sensor_msgs import point_cloud2
from std_msgs.msg import Header

from ohm_mirror_detector3d.msg import EchoPair

ROWS, COLS = 10, 12
WARM_UP = 100
ALLOWED_GROWTH_KB = 1024


def mirror_sweep(header):
    """A wall at 3 m and, in the middle 6 x 8 beams, a pane at 1.5 m with a far echo 3 m behind it:
    enough discontinuous beams for an object (plane, type test, vision cone)."""
    fields = [PointField(n, 4 * i, PointField.FLOAT32, 1) for i, n in enumerate(('x', 'y', 'z', 'intensity'))]
    echo1, echo2 = [], []
    for row in range(ROWS):
        for col in range(COLS):
            elevation, azimuth = math.radians(-9 + 2 * row), math.radians(-11 + 2 * col)
            d = np.array([math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                          math.sin(elevation)])
            wall = d * (3.0 / d[0])
            if 2 <= row < 8 and 2 <= col < 10:
                near, far = d * (1.5 / d[0]), d * (4.5 / d[0])
            else:
                near = far = wall
            echo1.append((*near, 100.0))
            echo2.append((*far, 50.0))
    pair = EchoPair(header=header)
    pair.echo1 = point_cloud2.create_cloud(header, fields, echo1)
    pair.echo2 = point_cloud2.create_cloud(header, fields, echo2)
    for cloud in (pair.echo1, pair.echo2):
        cloud.height, cloud.width, cloud.row_step = ROWS, COLS, COLS * cloud.point_step
    return pair


def node_pid(name):
    master = rosgraph.Master('/soak')
    uri = master.lookupNode(name)
    code, _, pid = xmlrpc.client.ServerProxy(uri).getPid('/soak')
    return pid


def rss_kb(pid):
    with open('/proc/%d/status' % pid) as f:
        for line in f:
            if line.startswith('VmRSS:'):
                return int(line.split()[1])
    raise RuntimeError('no VmRSS')


class Soak(unittest.TestCase):
    def test_rss_flat_over_many_sweeps(self):
        sweeps = rospy.get_param('~sweeps', 10000)
        answers = {}
        rospy.Subscriber('/prefilter/labelled', PointCloud2, lambda m: answers.__setitem__(m.header.stamp, m),
                         queue_size=10)
        publisher = rospy.Publisher('/prefilter/input', EchoPair, queue_size=1)
        deadline = time.time() + 60
        while publisher.get_num_connections() == 0 and time.time() < deadline:
            time.sleep(0.1)
        time.sleep(0.5)
        pid = node_pid('/manager')
        template = mirror_sweep(Header(frame_id='laser'))
        samples, started, lost = [], time.time(), 0
        for k in range(1, sweeps + 1):
            stamp = rospy.Time(1000 + k // 1000, (k % 1000) * 1000000)
            template.header.stamp = template.echo1.header.stamp = template.echo2.header.stamp = stamp
            for attempt in range(3):
                publisher.publish(template)
                wait_until = time.time() + 5.0
                while stamp not in answers and time.time() < wait_until:
                    time.sleep(0.0005)
                if stamp in answers:
                    break
                lost += 1
            answer = answers.pop(stamp, None)
            self.assertIsNotNone(answer, 'sweep %d not answered' % k)
            self.assertEqual(answer.width * answer.height, 2 * ROWS * COLS)
            if k == sweeps:
                labels = np.frombuffer(answer.data, np.uint8).reshape(-1, answer.point_step)[:, 16]
                print('labels of the last sweep (label: count): %s' % dict(zip(*np.unique(labels, return_counts=True))),
                      file=sys.stderr)
                # The sweep must exercise the whole pipeline: an object (plane, type test) and the
                # points behind it labelled through its vision cone (behindErrorS, -Reflective, -Transparent).
                self.assertTrue(set(labels.tolist()) & {3, 5, 7}, labels)
            if k == WARM_UP or k % 1000 == 0 or k == sweeps:
                samples.append((k, rss_kb(pid), time.time() - started))
        print('\nsweep   manager VmRSS [kB]   elapsed [s]', file=sys.stderr)
        for k, rss, elapsed in samples:
            print('%6d   %18d   %11.1f' % (k, rss, elapsed), file=sys.stderr)
        print('re-sent (queue of 1 lost a message): %d' % lost, file=sys.stderr)
        base = samples[0][1]
        growth = max(rss for _, rss, _ in samples) - base
        print('largest growth over sweep %d: %d kB (allowed %d kB)' % (WARM_UP, growth, ALLOWED_GROWTH_KB),
              file=sys.stderr)
        self.assertLessEqual(growth, ALLOWED_GROWTH_KB, samples)


if __name__ == '__main__':
    rospy.init_node('soak')
    rostest.rosrun('ohm_mirror_detector3d', 'soak', Soak)
