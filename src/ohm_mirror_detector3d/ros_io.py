"""ROS I/O of the simulator and the evaluator: numpy <-> messages, bags, a live sweep publisher.

This is the only module that imports ROS (rospy, rosbag, sensor_msgs, the
package's generated messages); everything else works on numpy arrays.

PointCloud2 <-> numpy goes through structured arrays whose field names are
the cloud's field names (`array_to_cloud`, `cloud_to_array`), so the echo
clouds, the ground truth and the filter's `labelled`/`cleaned` all use the
same two functions.
"""
import numpy as np

import rospy
from geometry_msgs.msg import Point
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header

from ohm_mirror_detector3d.msg import EchoPair, ReflectiveObject, ReflectiveObjectArray

from .labels import Label
from .simulate import GROUND_TRUTH_DTYPE, ground_truth_objects, physical_return_mask  # noqa: F401 (re-exported)

_TO_ROS = {np.dtype('int8'): PointField.INT8, np.dtype('uint8'): PointField.UINT8,
           np.dtype('int16'): PointField.INT16, np.dtype('uint16'): PointField.UINT16,
           np.dtype('int32'): PointField.INT32, np.dtype('uint32'): PointField.UINT32,
           np.dtype('float32'): PointField.FLOAT32, np.dtype('float64'): PointField.FLOAT64}
_FROM_ROS = {v: k for k, v in _TO_ROS.items()}

# Topic names (relative: resolved in the node's namespace, or written as /NAME into bags).
TOPIC_ECHO_PAIR, TOPIC_ECHO1, TOPIC_ECHO2 = 'echo_pair', 'echo1', 'echo2'
TOPIC_GROUND_TRUTH, TOPIC_GROUND_TRUTH_OBJECTS = 'ground_truth', 'ground_truth_objects'
FILTER_OUTPUTS = ('labelled', 'cleaned', 'objects')


def make_header(stamp, frame_id):
    h = Header()
    h.stamp = stamp if isinstance(stamp, rospy.Time) else rospy.Time.from_sec(float(stamp))
    h.frame_id = frame_id
    return h


def array_to_cloud(array, header, height=1, width=None):
    """A PointCloud2 holding a 1-D structured array (little endian, one point per element).

    height/width: organised layout (height * width == len(array)); default unorganised (1 x n).
    """
    array = np.ascontiguousarray(array)
    width = len(array) // height if width is None else width
    if height * width != len(array):
        raise ValueError('height * width = %d != %d points' % (height * width, len(array)))
    msg = PointCloud2()
    msg.header = header
    msg.height, msg.width = height, width
    for name in array.dtype.names:
        dt, offset = array.dtype.fields[name][:2]
        if dt.base.newbyteorder('<') not in _TO_ROS:
            raise TypeError('field %s: unsupported type %s' % (name, dt))
        count = int(np.prod(dt.shape)) if dt.shape else 1
        msg.fields.append(PointField(name=name, offset=offset, datatype=_TO_ROS[dt.base.newbyteorder('<')],
                                     count=count))
    msg.is_bigendian = False
    msg.point_step = array.dtype.itemsize
    msg.row_step = msg.point_step * width
    msg.data = array.astype(array.dtype.newbyteorder('<')).tobytes()
    has_xyz = all(f in array.dtype.names for f in 'xyz')
    msg.is_dense = bool(not has_xyz or np.isfinite(np.stack([array['x'], array['y'], array['z']])).all())
    return msg


def cloud_to_array(msg, fields=None):
    """The points of a PointCloud2 as a packed 1-D structured array (row-major for organised clouds).

    fields: optional list of field names to keep (KeyError if one is missing).
    """
    order = '>' if msg.is_bigendian else '<'
    names, formats, offsets = [], [], []
    for f in msg.fields:
        if f.datatype not in _FROM_ROS:
            continue
        base = _FROM_ROS[f.datatype].newbyteorder(order)
        names.append(f.name)
        formats.append(base if f.count <= 1 else (base, (f.count,)))
        offsets.append(f.offset)
    dtype = np.dtype({'names': names, 'formats': formats, 'offsets': offsets, 'itemsize': msg.point_step})
    n = msg.width * msg.height
    if msg.row_step == msg.point_step * msg.width:
        raw = np.frombuffer(bytes(msg.data), dtype=dtype, count=n)
    else:  # padded rows
        buf = np.frombuffer(bytes(msg.data), np.uint8).reshape(msg.height, msg.row_step)
        raw = np.frombuffer(buf[:, :msg.point_step * msg.width].tobytes(), dtype=dtype, count=n)
    keep = list(fields) if fields is not None else names
    missing = [k for k in keep if k not in names]
    if missing:
        raise KeyError('cloud has no field(s) %s (has %s)' % (missing, names))
    out = np.empty(n, [(k, raw.dtype.fields[k][0].newbyteorder('=')) for k in keep])
    for k in keep:
        out[k] = raw[k]
    return out


# ---------------------------------------------------------------------------------------------
# Objects

# The point counts of ReflectiveObject.msg.
OBJECT_COUNTS = ('surface_points', 'behind_points', 'phantom_points', 'transmitted_points', 'ambiguous_points',
                 'undecided_points', 'mirrored_points', 'tested_points')


def objects_to_msg(objects, header):
    """ReflectiveObjectArray from object dicts (id, type, corners (4,3), width, height, plane; optional counts)."""
    msg = ReflectiveObjectArray()
    msg.header = header
    for o in objects:
        m = ReflectiveObject()
        m.id = int(o.get('id', len(msg.objects)))
        m.type = int(o.get('type', ReflectiveObject.TYPE_UNKNOWN))
        m.corners = [Point(*map(float, c)) for c in np.asarray(o['corners'], float).reshape(4, 3)]
        m.width, m.height = float(o['width']), float(o['height'])
        # The surface-echo patch: the rectangle itself when the object did not grow.
        m.patch_corners = [Point(*map(float, c))
                           for c in np.asarray(o.get('patch_corners', o['corners']), float).reshape(4, 3)]
        m.patch_width = float(o.get('patch_width', o['width']))
        m.patch_height = float(o.get('patch_height', o['height']))
        m.growth_capped = bool(o.get('growth_capped', False))
        m.plane = [float(x) for x in o['plane']]
        for key in OBJECT_COUNTS:
            setattr(m, key, int(o.get(key, 0)))
        for key in ('real_fraction', 'landing_fitness', 'plane_correction'):
            setattr(m, key, float(o.get(key, float('nan') if key != 'plane_correction' else 0.0)))
        m.inlier_fraction = float(o.get('inlier_fraction', float('nan')))
        m.plane_refined = bool(o.get('plane_refined', False))
        m.mean_surface_intensity = float(o.get('mean_surface_intensity', float('nan')))
        msg.objects.append(m)
    return msg


def objects_from_msg(msg):
    """Object dicts (as metrics.py expects them) from a ReflectiveObjectArray."""
    out = []
    for m in msg.objects:
        out.append({
            'id': int(m.id), 'type': int(m.type),
            'corners': np.array([[c.x, c.y, c.z] for c in m.corners], float),
            'width': float(m.width), 'height': float(m.height), 'plane': np.array(m.plane, float),
            'patch_corners': np.array([[c.x, c.y, c.z] for c in m.patch_corners], float),
            'patch_width': float(m.patch_width), 'patch_height': float(m.patch_height),
            'growth_capped': bool(m.growth_capped),
            **{key: int(getattr(m, key)) for key in OBJECT_COUNTS},
            'inlier_fraction': float(m.inlier_fraction), 'real_fraction': float(m.real_fraction),
            'landing_fitness': float(m.landing_fitness), 'plane_refined': bool(m.plane_refined),
            'plane_correction': float(m.plane_correction), 'mean_surface_intensity': float(m.mean_surface_intensity),
        })
    return out


# ---------------------------------------------------------------------------------------------
# Sweeps

def sweep_to_messages(sweep, stamp, frame_id=None):
    """Messages of one sweep, keyed by topic name: echo_pair, echo1, echo2, ground_truth, ground_truth_objects.

    All share one header (stamp, frame); echo clouds are organised rows x cols.
    """
    header = make_header(stamp, frame_id or sweep.frame_id)
    echo1 = array_to_cloud(sweep.echo1, header, sweep.rows, sweep.cols)
    echo2 = array_to_cloud(sweep.echo2, header, sweep.rows, sweep.cols)
    pair = EchoPair(header=header, echo1=echo1, echo2=echo2)
    return {
        TOPIC_ECHO_PAIR: pair,
        TOPIC_ECHO1: echo1,
        TOPIC_ECHO2: echo2,
        TOPIC_GROUND_TRUTH: array_to_cloud(sweep.ground_truth, header),
        TOPIC_GROUND_TRUTH_OBJECTS: objects_to_msg(ground_truth_objects(sweep), header),
    }


def echo_pair_to_arrays(msg):
    """(echo1, echo2) structured arrays (x y z intensity) of an EchoPair."""
    return cloud_to_array(msg.echo1), cloud_to_array(msg.echo2)


def ground_truth_from_cloud(msg):
    """The ground-truth structured array (simulate.GROUND_TRUTH_DTYPE) from its PointCloud2. Clouds
    recorded before the double_echo field existed get it from the echoes' positions."""
    if any(f.name == 'double_echo' for f in msg.fields):
        return cloud_to_array(msg, GROUND_TRUTH_DTYPE.names)
    old = cloud_to_array(msg, [n for n in GROUND_TRUTH_DTYPE.names if n != 'double_echo'])
    out = np.zeros(len(old), GROUND_TRUTH_DTYPE)
    for name in old.dtype.names:
        out[name] = old[name]
    from .metrics import ground_truth_layout
    two = ground_truth_layout(out)[3]
    out['double_echo'] = two[out['beam']]
    return out


def filter_output_from_msgs(labelled, cleaned, objects=None):
    """{'labelled', 'cleaned', 'objects'} for metrics.evaluate_sweep from the filter's messages."""
    fields = ['x', 'y', 'z', 'label', 'echo', 'beam']
    return {
        'labelled': cloud_to_array(labelled, fields),
        'cleaned': cloud_to_array(cleaned, fields),
        'objects': objects_from_msg(objects) if objects is not None else [],
    }


# ---------------------------------------------------------------------------------------------
# Bags

def write_sweeps_bag(path, sweeps, start_time=1000.0, period=1.0, frame_id=None, topic_prefix='/',
                     to_messages=None, progress=None, sensor_path=None, fixed_frame=None):
    """Writes sweeps to a bag (no master needed): topics prefix + echo_pair, echo1, echo2, ground_truth,
    ground_truth_objects (or those of `to_messages(sweep, stamp, frame_id)`, default sweep_to_messages);
    sweep k is stamped start_time + k * period. Returns the stamps.

    sensor_path: the sweeps' sensor_path.SensorPath; then /tf holds fixed_frame (default
    sensor_path.FIXED_FRAME) <- the sweep's frame at every sweep's stamp, written before its clouds.
    progress: optional progress.Progress, told of every sweep written."""
    import rosbag
    to_messages = to_messages or sweep_to_messages
    stamps = []
    with rosbag.Bag(path, 'w') as bag:
        for k, sweep in enumerate(sweeps):
            stamp = rospy.Time.from_sec(start_time + k * period)
            if sensor_path is not None:
                bag.write('/tf', path_transform_msg(sensor_path, k, stamp, frame_id or sweep.frame_id, fixed_frame),
                          stamp)
            for topic, msg in to_messages(sweep, stamp, frame_id).items():
                bag.write(topic_prefix + topic, msg, stamp)
            stamps.append(stamp)
            if progress is not None:
                progress.update(len(stamps))
    if progress is not None:
        progress.finish()
    return stamps


def path_transform_msg(sensor_path, k, stamp, sweep_frame, fixed_frame=None, offset=(0.0, 0.0, 0.0)):
    """tf2_msgs/TFMessage: fixed_frame (default sensor_path.FIXED_FRAME) <- sweep_frame at sweep k of a
    sensor_path.SensorPath, stamped `stamp` (seconds or rospy.Time). `offset`: where the scanner's
    optical centre is in sweep_frame (axes parallel; scan_sequence's laser_offset)."""
    from .sensor_path import FIXED_FRAME
    translation, quaternion = sensor_path.transform(k)
    rotation = sensor_path.poses[k].rotation()
    origin = np.asarray(translation) - rotation @ np.asarray(offset, float)
    seconds = stamp.to_sec() if isinstance(stamp, rospy.Time) else float(stamp)
    return transform_msg(seconds, tuple(float(v) for v in origin), quaternion, fixed_frame or FIXED_FRAME,
                         sweep_frame)


def read_bag_by_stamp(path, topics):
    """{topic: {header stamp (rospy.Time): message}} for the given topics of a bag."""
    import rosbag
    out = {t: {} for t in topics}
    with rosbag.Bag(path) as bag:
        for topic, msg, t in bag.read_messages(topics=list(topics)):
            stamp = msg.header.stamp if hasattr(msg, 'header') else t
            out[topic][stamp] = msg
    return out


# ---------------------------------------------------------------------------------------------
# Live publishing

class SweepPublisher:
    """Publishes sweeps on echo_pair, echo1, echo2, ground_truth, ground_truth_objects (node namespace).

    With `to_messages(sweep, stamp, frame_id)` (a {topic: message} dict, e.g. the dual-return cloud's)
    it publishes those topics instead; `input_topics` are those the pre-filter reads, published last,
    of the types in `input_types` (default PointCloud2).
    """

    def __init__(self, queue_size=2, latch=False, to_messages=None,
                 input_topics=(TOPIC_ECHO1, TOPIC_ECHO2, TOPIC_ECHO_PAIR), input_types=None, tf=False):
        self.to_messages = to_messages or sweep_to_messages
        self.input_topics = tuple(input_topics)
        self.queue_size, self.latch = queue_size, latch
        self.publishers = {}
        if to_messages is None:
            for topic, kind in ((TOPIC_ECHO_PAIR, EchoPair), (TOPIC_ECHO1, PointCloud2), (TOPIC_ECHO2, PointCloud2)):
                self._advertise(topic, kind)
        else:
            for topic in self.input_topics:
                self._advertise(topic, (input_types or {}).get(topic, PointCloud2))
        self._advertise(TOPIC_GROUND_TRUTH, PointCloud2)
        self._advertise(TOPIC_GROUND_TRUTH_OBJECTS, ReflectiveObjectArray)
        if tf:
            from tf2_msgs.msg import TFMessage
            self.publishers['/tf'] = rospy.Publisher('/tf', TFMessage, queue_size=100)

    def _advertise(self, topic, kind):
        self.publishers[topic] = rospy.Publisher(topic, kind, queue_size=self.queue_size, latch=self.latch)

    def publish(self, sweep, stamp=None, frame_id=None, transform=None):
        """transform: a TFMessage (e.g. path_transform_msg) published on /tf before the sweep (needs tf=True)."""
        stamp = stamp if stamp is not None else rospy.Time.now()
        msgs = self.to_messages(sweep, stamp, frame_id)
        if transform is not None:
            self.publishers['/tf'].publish(transform)
        # Ground truth first, so an evaluator has it before the filter's outputs of this stamp.
        for topic in (TOPIC_GROUND_TRUTH, TOPIC_GROUND_TRUTH_OBJECTS) + self.input_topics:
            self.publishers[topic].publish(msgs[topic])
        return stamp


# ---------------------------------------------------------------------------------------------
# Rotating Hokuyo as single multi-echo scans plus tf (input mode multi_echo_scan)

TOPIC_SCAN_ECHOES = 'scan_echoes'


def scan_to_msg(scan, geometry, frame_id, ranges=None, intensities=None):
    """sensor_msgs/MultiEchoLaserScan of a scan_sequence.Scan (ranges/intensities override its echoes)."""
    from sensor_msgs.msg import LaserEcho, MultiEchoLaserScan
    msg = MultiEchoLaserScan()
    msg.header = make_header(rospy.Time.from_sec(scan.stamp), frame_id)
    msg.angle_min, msg.angle_max = geometry.angle_min, geometry.angle_max
    msg.angle_increment = geometry.angle_increment
    msg.time_increment, msg.scan_time = geometry.time_increment, geometry.scan_time
    msg.range_min, msg.range_max = geometry.range_min, geometry.range_max
    msg.ranges = [LaserEcho(echoes=e) for e in (scan.ranges if ranges is None else ranges)]
    msg.intensities = [LaserEcho(echoes=e) for e in (scan.intensities if intensities is None else intensities)]
    return msg


def transform_msg(stamp, translation, quaternion, parent, child):
    """tf2_msgs/TFMessage with one transform parent <- child."""
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage
    t = TransformStamped()
    t.header = make_header(rospy.Time.from_sec(stamp), parent)
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = translation
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = quaternion
    return TFMessage(transforms=[t])


def scan_stream_messages(stream, count, scan_frame='laser', corrupt_scans=()):
    """Messages of `count` sweeps of a scan_sequence.ScanStream in publishing order, as (topic, stamp, msg):
    the ground truth of each sweep first (stamped like the assembled sweep), then per scan the tf at the
    start of the next scan (so the scan's last beam can be projected) and the scan. One more scan follows,
    the first of the next half rotation, which completes the last sweep. `corrupt_scans`: indices g of scans
    preceded by a malformed copy (intensities shorter than ranges), for tests of the error path.
    count <= 0: without end. A generator: sweeps are simulated as they are needed."""
    geometry = stream.geometry

    def tf_at(g):
        translation, quaternion = stream.laser_pose(g)
        msg = transform_msg(stream.scan_stamp(g), translation, quaternion, stream.sweep_frame, scan_frame)
        if stream.path is not None:   # the sweep frame on its path, with the pose of the sweep scan g belongs to
            msg.transforms += path_transform_msg(stream.path, stream.path_index(g), stream.scan_stamp(g),
                                                 stream.sweep_frame, stream.fixed_frame, stream.laser_offset).transforms
        return msg

    yield '/tf', stream.scan_stamp(0), tf_at(0)
    j = 0
    while count <= 0 or j <= count:
        sweep = stream.sweep(j)
        scans = stream.scans(j, sweep)
        if count > 0 and j == count:
            scans = scans[:1]
        else:
            truth = stream.ground_truth(sweep)
            for topic, msg in sweep_to_messages(truth, rospy.Time.from_sec(stream.sweep_stamp(j)),
                                                stream.sweep_frame).items():
                if topic in (TOPIC_GROUND_TRUTH, TOPIC_GROUND_TRUTH_OBJECTS):
                    yield topic, stream.sweep_stamp(j), msg
        for scan in scans:
            yield '/tf', stream.scan_stamp(scan.index + 1), tf_at(scan.index + 1)
            if scan.index in corrupt_scans:
                yield TOPIC_SCAN_ECHOES, scan.stamp, scan_to_msg(scan, geometry, scan_frame,
                                                                 intensities=scan.intensities[:-1])
            yield TOPIC_SCAN_ECHOES, scan.stamp, scan_to_msg(scan, geometry, scan_frame)
        j += 1


def write_scan_stream_bag(path, stream, count, scan_frame='laser', topic_prefix='/', progress=None):
    """Writes /scan_echoes, /tf, /ground_truth and /ground_truth_objects of `count` sweeps (plus the scan that
    completes the last one) to a bag, each at its stamp. Returns the ground-truth stamps.

    progress: optional progress.Progress, told of every sweep completed."""
    import rosbag
    stamps = []
    with rosbag.Bag(path, 'w') as bag:
        for topic, stamp, msg in scan_stream_messages(stream, count, scan_frame):
            name = topic if topic.startswith('/') else topic_prefix + topic
            bag.write(name, msg, rospy.Time.from_sec(stamp))
            if topic == TOPIC_GROUND_TRUTH:
                stamps.append(msg.header.stamp)
                if progress is not None:
                    progress.update(len(stamps))
    if progress is not None:
        progress.finish()
    return stamps


class ScanStreamPublisher:
    """Publishes a scan stream live: scan_echoes, ground_truth, ground_truth_objects (node namespace) and /tf."""

    def __init__(self, queue_size=1000):
        from sensor_msgs.msg import MultiEchoLaserScan
        from tf2_msgs.msg import TFMessage
        self.publishers = {
            TOPIC_SCAN_ECHOES: rospy.Publisher(TOPIC_SCAN_ECHOES, MultiEchoLaserScan, queue_size=queue_size),
            '/tf': rospy.Publisher('/tf', TFMessage, queue_size=queue_size),
            TOPIC_GROUND_TRUTH: rospy.Publisher(TOPIC_GROUND_TRUTH, PointCloud2, queue_size=10),
            TOPIC_GROUND_TRUTH_OBJECTS: rospy.Publisher(TOPIC_GROUND_TRUTH_OBJECTS, ReflectiveObjectArray,
                                                        queue_size=10),
        }

    def publish(self, topic, msg):
        self.publishers[topic].publish(msg)
