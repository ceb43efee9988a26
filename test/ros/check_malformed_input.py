#!/usr/bin/python3
"""rostest checker: malformed input on one input mode (~mode) of a running pre-filter nodelet.

The good sweep is sent first and its labelled output kept as the reference. Then, for every
bad case: the bad message(s), then good sweeps until one is answered. Checked for each case:
- a case the node must refuse gives an ERROR on /rosout naming the input topic and the problem,
  and no output;
- a case whose data is still usable (no intensity, all-NaN, +-Inf, points at 0, empty, unknown
  frame, stamp going backwards, 10 M points) gives an output that accounts for every input point
  with the labels it must have (nanPoint for points without a usable return);
- the next good sweep gives exactly the reference output (the node is alive and unharmed).
"""
import copy
import math
import os
import struct
import sys
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import LaserEcho, MultiEchoLaserScan, PointCloud2, PointField
from std_msgs.msg import Header

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pair_fixture import make_pair  # noqa: E402

from ohm_mirror_detector3d.msg import EchoPair  # noqa: E402
from ohm_mirror_detector3d.hokuyo3d_legacy import LEGACY_TYPE, legacy_classes  # noqa: E402

NAN_POINT = 8
LABEL_OFFSET = 16
OUTPUT_STEP = 24
ANSWER_TIMEOUT = 30.0


def labels_of(cloud):
    data = np.frombuffer(cloud.data, np.uint8).reshape(-1, OUTPUT_STEP) if cloud.data else np.zeros((0, OUTPUT_STEP))
    return data[:, LABEL_OFFSET]


def set_xyz(cloud, values):
    """A copy of `cloud` whose x, y, z (float32 at offsets 0, 4, 8) are all set to `values`
    (a scalar or one value per point)."""
    out = copy.deepcopy(cloud)
    n = out.width * out.height
    data = np.frombuffer(bytes(out.data), np.uint8).reshape(n, out.point_step).copy()
    xyz = np.broadcast_to(np.asarray(values, np.float32).reshape(-1, 1), (n, 3)).astype(np.float32)
    data[:, 0:12] = xyz.view(np.uint8).reshape(n, 12)
    out.data = data.tobytes()
    return out


def rename_field(cloud, old, new):
    out = copy.deepcopy(cloud)
    for f in out.fields:
        if f.name == old:
            f.name = new
    return out


def retype_field(cloud, name, datatype):
    out = copy.deepcopy(cloud)
    for f in out.fields:
        if f.name == name:
            f.datatype = datatype
    return out


def drop_field(cloud, name):
    out = copy.deepcopy(cloud)
    out.fields = [f for f in out.fields if f.name != name]
    return out


def truncate(cloud, points):
    out = copy.deepcopy(cloud)
    out.height, out.width = 1, points
    out.row_step = out.point_step * points
    out.data = bytes(out.data)[:out.row_step]
    return out


def wider_than_data(cloud):
    out = copy.deepcopy(cloud)
    out.width += 1
    out.row_step = out.point_step * out.width
    return out


def short_point_step(cloud):
    """point_step 8: the z field (offset 8) no longer fits in a point; row_step and data follow."""
    out = copy.deepcopy(cloud)
    n = out.width * out.height
    data = np.frombuffer(bytes(out.data), np.uint8).reshape(n, out.point_step)[:, :8]
    out.point_step, out.row_step, out.data = 8, 8 * out.width, data.tobytes()
    return out


def huge_dual_return_cloud(header, points=10 * 1000 * 1000):
    """10 M points at the origin (no return: every one nanPoint), as fast to build as numpy allows."""
    cloud = PointCloud2(header=header, height=1, width=points, is_bigendian=False, point_step=16,
                        row_step=16 * points, is_dense=False)
    cloud.fields = [PointField('x', 0, PointField.FLOAT32, 1), PointField('y', 4, PointField.FLOAT32, 1),
                    PointField('z', 8, PointField.FLOAT32, 1), PointField('return_type', 12, PointField.UINT8, 1),
                    PointField('ring', 14, PointField.UINT16, 1)]
    cloud.data = bytes(16 * points)
    return cloud


def huge_echo_cloud(header, points=5 * 1000 * 1000):
    """An echo cloud of `points` points at the origin (x y z intensity, float32): nanPoint, all of them."""
    cloud = PointCloud2(header=header, height=1, width=points, is_bigendian=False, point_step=16,
                        row_step=16 * points, is_dense=False)
    cloud.fields = [PointField(n, 4 * i, PointField.FLOAT32, 1) for i, n in enumerate(('x', 'y', 'z', 'intensity'))]
    cloud.data = bytes(16 * points)
    return cloud


def dual_return_cloud(header):
    """12 beams of ring 0 and 1 at distinct azimuths, two returns each: some discontinuous
    (echo 2 farther than d_thres), some agreeing, one single return (echo 2 NaN)."""
    points = []
    for ring in range(2):
        for i in range(6):
            azimuth = math.radians(10.0 * i)
            near = 2.0 + 0.3 * i
            far = near + (1.0 if i % 2 == 0 else 0.01)
            z = 0.3 * ring
            for ret, r in ((1, near), (2, far if i != 5 else float('nan'))):
                points.append((r * math.cos(azimuth), r * math.sin(azimuth), z, 10.0 * ret, ret, ring))
    dtype = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('intensity', '<f4'), ('return_type', 'u1'),
                      ('pad', 'u1'), ('ring', '<u2')])
    array = np.array(points, dtype=[(n, t) for n, t in dtype.descr if n != 'pad'])
    full = np.zeros(len(array), dtype)
    for name in array.dtype.names:
        full[name] = array[name]
    cloud = PointCloud2(header=header, height=1, width=len(full), is_bigendian=False, point_step=dtype.itemsize,
                        row_step=dtype.itemsize * len(full), is_dense=False, data=full.tobytes())
    cloud.fields = [PointField('x', 0, PointField.FLOAT32, 1), PointField('y', 4, PointField.FLOAT32, 1),
                    PointField('z', 8, PointField.FLOAT32, 1), PointField('intensity', 12, PointField.FLOAT32, 1),
                    PointField('return_type', 16, PointField.UINT8, 1), PointField('ring', 18, PointField.UINT16, 1)]
    return cloud


class Case:
    """One bad input. `messages(stamp)` returns what to publish; `error` a text the ERROR on
    /rosout must contain (None: the data is usable and must be answered); `answer_labels`
    checks the answer's labels (None: any, as long as every input point is there)."""

    def __init__(self, name, messages, error=None, answer_points=None, all_nan=False, stamp_offset=0):
        self.name, self.messages, self.error = name, messages, error
        self.stamp_offset = stamp_offset  # the answer's stamp relative to the case's header stamp [s]
        self.answer_points, self.all_nan = answer_points, all_nan


class MalformedInput(unittest.TestCase):
    mode = None

    @classmethod
    def setUpClass(cls):
        cls.mode = rospy.get_param('~mode')
        cls.node = rospy.get_param('~node')
        cls.log = []
        cls.answers = {}
        cls.stamp_sec = 1000
        rospy.Subscriber('/rosout', Log, cls.log.append, queue_size=1000)
        rospy.Subscriber(cls.node + '/labelled', PointCloud2, cls.on_labelled, queue_size=5, buff_size=2 ** 29)
        if cls.mode == 'pair':
            cls.topic = cls.node + '/input'
            cls.pubs = [rospy.Publisher(cls.topic, EchoPair, queue_size=10)]
        elif cls.mode == 'two_topics':
            cls.topic = cls.node + '/echo1'
            cls.pubs = [rospy.Publisher(cls.node + '/echo1', PointCloud2, queue_size=10),
                        rospy.Publisher(cls.node + '/echo2', PointCloud2, queue_size=10)]
        elif cls.mode == 'dual_return':
            cls.topic = cls.node + '/input'
            cls.pubs = [rospy.Publisher(cls.topic, PointCloud2, queue_size=10)]
        elif cls.mode == 'hokuyo3d_legacy':
            cls.topic = cls.node + '/input'
            cls.classes = legacy_classes()
            cls.pubs = [rospy.Publisher(cls.topic, cls.classes[LEGACY_TYPE], queue_size=10)]
        else:
            cls.topic = cls.node + '/input'
            cls.pubs = [rospy.Publisher(cls.topic, MultiEchoLaserScan, queue_size=50)]
            cls.tf = tf2_ros.StaticTransformBroadcaster()
            laser = TransformStamped()
            laser.header.frame_id, laser.child_frame_id = 'map', 'laser'
            laser.transform.translation.z = 0.5
            laser.transform.rotation.w = 1.0
            cls.tf.sendTransform(laser)
            cls.scan_time = 100.0
        deadline = rospy.Time.now() + rospy.Duration(60.0)
        while any(p.get_num_connections() == 0 for p in cls.pubs) and rospy.Time.now() < deadline:
            rospy.sleep(0.1)
        rospy.sleep(0.5)

    @classmethod
    def on_labelled(cls, msg):
        cls.answers[msg.header.stamp] = msg

    # ---- messages per mode -------------------------------------------------------------------
    def next_header(self, frame='laser'):
        type(self).stamp_sec += 1
        return Header(stamp=rospy.Time(self.stamp_sec, 0), frame_id=frame)

    def clouds(self, header):
        """The good input as a list of PointCloud2 (pair/two_topics: echo1, echo2; dual_return: one)."""
        if self.mode == 'dual_return':
            return [dual_return_cloud(header)]
        pair = make_pair(header)
        return [pair.echo1, pair.echo2]

    def cloud_messages(self, clouds, header):
        """What to publish for a list of clouds: an EchoPair, two clouds, or one cloud."""
        for c in clouds:
            c.header = header
        if self.mode == 'pair':
            return [(0, EchoPair(header=header, echo1=clouds[0], echo2=clouds[1]))]
        return list(enumerate(clouds))

    def legacy_message(self, header, echoes=None, mask=None, coords_extra=0, intensity_short=False):
        coord_dist, coord, dist = (self.classes['ohm_hokuyo3d/' + t] for t in ('CoordDist', 'Coord', 'Dist'))
        msg = self.classes[LEGACY_TYPE]()
        pair = make_pair(header)
        for k, cloud in enumerate((pair.echo1, pair.echo2)):
            n = cloud.width
            points = np.frombuffer(bytes(cloud.data), np.float32).reshape(n, 4)[:, :3].copy()
            if echoes is not None:
                points = np.broadcast_to(np.float32(echoes), points.shape).copy()
            valid = np.isfinite(points).all(axis=1) if mask is None else np.full(n, mask)
            coords = np.where(valid[:, None], points, 0.0).astype(np.float32).ravel()
            if k == 1 and coords_extra:
                coords = np.concatenate([coords, np.zeros(coords_extra, np.float32)])
            intensity = np.full(n - (1 if intensity_short else 0), 5.0, np.float32)
            c = coord(header=header, fragmentid=0, fragmentsize=1, coords=coords, normals=np.zeros(3 * n, np.float32),
                      mask=valid.astype(np.uint8), intensity=intensity, objectType=np.zeros(n, np.int32))
            d = dist(header=header, dists=np.zeros(n, np.float32), phi=np.zeros(1, np.float32),
                     mask=valid.astype(np.uint8))
            msg.coorddist.append(coord_dist(coord=c, dist=d))
        return msg

    def scan(self, ranges, frame='laser', stamp=None, intensities=None, time_increment=0.0005):
        if stamp is None:
            type(self).scan_time += 0.02
            stamp = self.scan_time
        msg = MultiEchoLaserScan()
        msg.header = Header(stamp=rospy.Time.from_sec(stamp), frame_id=frame)
        msg.angle_min, msg.angle_increment = -0.5, 0.1
        msg.angle_max = msg.angle_min + (len(ranges) - 1) * msg.angle_increment if ranges else msg.angle_min
        msg.time_increment, msg.scan_time = time_increment, 0.02
        msg.range_min, msg.range_max = 0.02, 30.0
        msg.ranges = [LaserEcho(echoes=list(r)) for r in ranges]
        intensities = intensities if intensities is not None else [[100.0] * len(r) for r in ranges]
        msg.intensities = [LaserEcho(echoes=list(i)) for i in intensities]
        return msg

    GOOD_SCAN = [[2.0]] * 4 + [[1.5, 3.0]] * 4 + [[2.5]] * 4

    def good_messages(self):
        """The good sweep: (publisher index, message) pairs, and the stamp its answer will carry
        (None for multi_echo_scan, whose sweeps are cut by time and answered a sweep later)."""
        if self.mode == 'multi_echo_scan':
            return [(0, self.scan(self.GOOD_SCAN)) for _ in range(5)], None
        header = self.next_header()
        if self.mode == 'hokuyo3d_legacy':
            return [(0, self.legacy_message(header))], header.stamp
        return self.cloud_messages(self.clouds(header), header), header.stamp

    # ---- sending and waiting -----------------------------------------------------------------
    def publish(self, messages):
        for index, msg in messages:
            self.pubs[index].publish(msg)
            rospy.sleep(0.01)

    def wait_answer(self, stamp, timeout=ANSWER_TIMEOUT):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while stamp not in self.answers and rospy.Time.now() < deadline and not rospy.is_shutdown():
            rospy.sleep(0.02)
        return self.answers.get(stamp)

    def errors_since(self, start):
        return [m.msg for m in self.log[start:] if m.level >= Log.ERROR]

    def good_round(self):
        """Publishes good sweeps until one is answered; returns that answer."""
        if self.mode == 'multi_echo_scan':
            # A sweep is complete when the first scan of the next one comes: several rounds.
            for _ in range(4):
                before = set(self.answers)
                messages, _ = self.good_messages()
                self.publish(messages)
                deadline = rospy.Time.now() + rospy.Duration(3.0)
                while rospy.Time.now() < deadline:
                    new = [s for s in self.answers if s not in before]
                    full = [s for s in new if self.answers[s].width == 2 * 5 * len(self.GOOD_SCAN)]
                    # Sweeps are cut by time: one that straddles a bad scan's slot is not a
                    # good sweep; the next ones must be.
                    reference = getattr(self, 'reference', None)
                    same = [s for s in full if reference is not None and self.answers[s].data == reference.data]
                    if same or (full and reference is None):
                        return self.answers[max(same or full)]
                    rospy.sleep(0.05)
            return None
        messages, stamp = self.good_messages()
        self.publish(messages)
        return self.wait_answer(stamp)

    # ---- the cases ---------------------------------------------------------------------------
    def cloud_cases(self):
        mode = self.mode
        pair_mode = mode in ('pair', 'two_topics')
        n_input = 2 * 7 if pair_mode else 24

        def mutate(function, both=True):
            def messages(header):
                clouds = self.clouds(header)
                clouds = [function(c) if (both or k == 0) else c for k, c in enumerate(clouds)]
                return self.cloud_messages(clouds, header)
            return messages

        cases = [
            Case('missing x', mutate(lambda c: rename_field(c, 'x', 'q')), error="no 'x' field"),
            Case('missing z', mutate(lambda c: rename_field(c, 'z', 'w')), error="no 'z' field"),
            Case('x of the wrong type', mutate(lambda c: retype_field(c, 'x', PointField.FLOAT64)),
                 error="field 'x' has datatype 8, expected FLOAT32"),
            Case('intensity of an unknown type', mutate(lambda c: retype_field(c, 'intensity', 42)),
                 error="field 'intensity' has unknown datatype 42"),
            Case('no intensity', mutate(lambda c: drop_field(c, 'intensity')), answer_points=n_input),
            Case('width * height does not match the data', mutate(wider_than_data), error='data holds'),
            Case('point_step too small for the fields', mutate(short_point_step), error='does not fit in point_step 8'),
            Case('empty cloud', mutate(lambda c: truncate(c, 0)), answer_points=0),
            Case('all NaN', mutate(lambda c: set_xyz(c, float('nan'))), answer_points=n_input, all_nan=True),
            Case('+-Inf', mutate(lambda c: set_xyz(c, [math.inf if i % 2 else -math.inf
                                                        for i in range(c.width * c.height)])),
                 answer_points=n_input, all_nan=True),
            Case('points at 0', mutate(lambda c: set_xyz(c, 0.0)), answer_points=n_input, all_nan=True),
            Case('unknown frame', lambda header: self.cloud_messages(
                self.clouds(header), Header(stamp=header.stamp, frame_id='no_such_frame')), answer_points=n_input),
            Case('stamp going backwards', lambda header: self.cloud_messages(
                self.clouds(header), Header(stamp=header.stamp - rospy.Duration(5), frame_id='laser')),
                answer_points=n_input, stamp_offset=-5),
        ]
        if pair_mode:
            # 10 M input points: 5 M per echo.
            cases.append(Case('10 M points', lambda header: self.cloud_messages(
                [huge_echo_cloud(header), huge_echo_cloud(header)], header),
                answer_points=10 * 1000 * 1000, all_nan=True))
            cases.append(Case('echoes of different sizes', mutate(lambda c: truncate(c, 5), both=False),
                              error='echo1 has 5 points but echo2 has 7'))
            if mode == 'two_topics':
                # Each echo names its own problem (echo1 / echo2).
                cases.append(Case('echoes without y', mutate(lambda c: rename_field(c, 'y', 'v')),
                                  error="echo1 has no 'y' field"))
        else:
            cases.append(Case('no return-index field', mutate(lambda c: rename_field(c, 'return_type', 'kind')),
                              error='has no return-index field'))
            cases.append(Case('return index of a float type',
                              mutate(lambda c: retype_field(c, 'return_type', PointField.FLOAT32)),
                              error="field 'return_type' has datatype 7, expected an integer type"))
            cases.append(Case('10 M points', lambda header: [(0, huge_dual_return_cloud(header))],
                              answer_points=10 * 1000 * 1000, all_nan=True))
        return cases

    def legacy_cases(self):
        n = 2 * 7
        return [
            Case('echoes of different sizes', lambda h: [(0, self.legacy_message(h, coords_extra=3))],
                 error='echo 2 has 8 points but echo 1 has 7'),
            Case('coords not 3 per point', lambda h: [(0, self.legacy_message(h, coords_extra=1))],
                 error='not 3 per point'),
            Case('intensity shorter than the points', lambda h: [(0, self.legacy_message(h, intensity_short=True))],
                 error="coord.intensity' holds 6 values for 7 points"),
            Case('all masked out', lambda h: [(0, self.legacy_message(h, mask=False))], answer_points=n,
                 all_nan=True),
            Case('all NaN', lambda h: [(0, self.legacy_message(h, echoes=float('nan'), mask=True))],
                 answer_points=n, all_nan=True),
            Case('+Inf', lambda h: [(0, self.legacy_message(h, echoes=math.inf, mask=True))], answer_points=n,
                 all_nan=True),
            Case('points at 0', lambda h: [(0, self.legacy_message(h, echoes=0.0, mask=True))], answer_points=n,
                 all_nan=True),
            Case('unknown frame', lambda h: [(0, self.legacy_message(Header(stamp=h.stamp, frame_id='nowhere')))],
                 answer_points=n),
            Case('stamp going backwards', lambda h: [(0, self.legacy_message(
                Header(stamp=h.stamp - rospy.Duration(5), frame_id='laser')))], answer_points=n, stamp_offset=-5),
        ]

    def scan_cases(self):
        good = self.GOOD_SCAN
        return [
            Case('ranges and intensities of different lengths',
                 lambda h: [(0, self.scan(good, intensities=[[1.0]] * (len(good) - 1)))], error='intensities'),
            Case('a beam with more ranges than intensities',
                 lambda h: [(0, self.scan(good, intensities=[[1.0]] * len(good)))], error='intensity echoes'),
            Case('zero stamp', lambda h: [(0, self.scan(good, stamp=0.0))], error='header.stamp is zero'),
            # Found by the fuzzer: ros::Duration threw out of the callback.
            Case('time_increment of 1e27 s', lambda h: [(0, self.scan(good, time_increment=1e27))],
                 error='(time_increment) take'),
            Case('no beams', lambda h: [(0, self.scan([]))], error='no beams'),
            Case('unknown frame', lambda h: [(0, self.scan(good, frame='no_such_frame'))],
                 error="frame_id 'no_such_frame' is unknown to tf"),
            Case('stamp going backwards', lambda h: [(0, self.scan(good, stamp=self.scan_time - 1.0))]),
            Case('all NaN', lambda h: [(0, self.scan([[float('nan')]] * len(good)))]),
            Case('+-Inf', lambda h: [(0, self.scan([[math.inf, -math.inf]] * len(good)))]),
            Case('ranges at 0', lambda h: [(0, self.scan([[0.0]] * len(good)))]),
        ]

    def run_case(self, case):
        log_start = len(self.log)
        header = None
        if self.mode not in ('multi_echo_scan',):
            header = self.next_header()
        self.publish(case.messages(header))
        stamp = header.stamp + rospy.Duration(case.stamp_offset) if header is not None else None
        problems = []
        if case.error is not None:
            deadline = rospy.Time.now() + rospy.Duration(ANSWER_TIMEOUT)
            while not any(case.error in e for e in self.errors_since(log_start)) and rospy.Time.now() < deadline:
                rospy.sleep(0.05)
            errors = self.errors_since(log_start)
            matching = [e for e in errors if case.error in e]
            if not matching:
                problems.append('no ERROR containing %r on /rosout (errors: %s)' % (case.error, errors))
            elif not any(self.topic in e for e in matching):
                problems.append('the error does not name the topic %s: %s' % (self.topic, matching))
        elif stamp is not None:
            answer = self.wait_answer(stamp, timeout=120.0 if case.answer_points and case.answer_points > 10 ** 6
                                      else ANSWER_TIMEOUT)
            if answer is None:
                problems.append('usable input not answered')
            else:
                points = answer.width * answer.height
                if case.answer_points is not None and points != case.answer_points:
                    problems.append('answer holds %d points, expected %d' % (points, case.answer_points))
                if case.all_nan and points and not np.all(labels_of(answer) == NAN_POINT):
                    problems.append('points without a usable return not all nanPoint: %s'
                                    % np.unique(labels_of(answer)))
                self.answers.pop(stamp, None)
        answer = self.good_round()
        if answer is None:
            problems.append('the next good sweep was not answered: the node is dead or stuck')
        elif bytes(answer.data) != bytes(self.reference.data):
            problems.append('the next good sweep was answered differently than before (%d points, labels %s)'
                            % (answer.width, np.unique(labels_of(answer), return_counts=True)))
        if stamp is not None and case.error is not None and stamp in self.answers:
            problems.append('a refused input was answered')
        return problems

    def test_every_bad_input_refused_or_handled_and_the_next_good_sweep_correct(self):
        reference = self.good_round()
        self.assertIsNotNone(reference, 'the good sweep was not answered at all')
        type(self).reference = reference
        if self.mode == 'hokuyo3d_legacy':
            cases = self.legacy_cases()
        elif self.mode == 'multi_echo_scan':
            cases = self.scan_cases()
        else:
            cases = self.cloud_cases()
        failures = {}
        for case in cases:
            problems = self.run_case(case)
            print('%s / %s: %s' % (self.mode, case.name, 'ok' if not problems else '; '.join(problems)),
                  file=sys.stderr)
            if problems:
                failures[case.name] = problems
        self.assertEqual(failures, {})


if __name__ == '__main__':
    rospy.init_node('check_malformed_input', anonymous=True)
    rostest.rosrun('ohm_mirror_detector3d', 'malformed_input_' + rospy.get_param('~mode'), MalformedInput)
