#!/usr/bin/python3
"""Writes the fuzzer's seed corpus (test/fuzz/corpus): one small valid input per input mode and
parameter set, in the layout of fuzz_entry.h (mode byte, parameter-set byte, serialized message).

The scene is tiny on purpose (a wall, a mirror patch in front of it with double echoes, and a
few single returns) so that every seed stays under the fuzzer's -max_len and, with the small
parameter sets, reaches object extraction and the type test.
Run: /usr/bin/python3 test/fuzz/make_seed_corpus.py test/fuzz/corpus  (after sourcing the workspace).
"""
import io
import math
import os
import struct
import sys

import rospy
from sensor_msgs.msg import LaserEcho, MultiEchoLaserScan, PointField
from sensor_msgs import point_cloud2
from std_msgs.msg import Header

from ohm_mirror_detector3d.msg import EchoPair
from ohm_mirror_detector3d.hokuyo3d_legacy import LEGACY_TYPE, legacy_classes

MODES = {'pair': 0, 'two_topics': 1, 'dual_return': 2, 'hokuyo3d_legacy': 3, 'multi_echo_scan': 4}


def serialize(msg):
    buf = io.BytesIO()
    msg.serialize(buf)
    return buf.getvalue()


def scene_beams():
    """(echo1, echo2) xyz per beam: 5 x 6 beams, a mirror patch at x = 1.5 in front of a wall at
    x = 3; through the mirror the far echo lands behind it (a phantom of the wall)."""
    beams = []
    for row in range(5):
        for col in range(6):
            y, z = -0.5 + 0.2 * col, -0.4 + 0.2 * row
            wall = (3.0, 2 * y, 2 * z)
            if 1 <= row <= 3 and 1 <= col <= 4:
                beams.append(((1.5, y, z), (4.5, 3 * y, 3 * z)))
            else:
                beams.append((wall, wall))
    beams[0] = ((float('nan'),) * 3, (float('inf'), 0.0, 0.0))
    return beams


def echo_pair(header):
    fields = [PointField(n, 4 * i, PointField.FLOAT32, 1) for i, n in enumerate(('x', 'y', 'z', 'intensity'))]
    beams = scene_beams()
    pair = EchoPair(header=header)
    pair.echo1 = point_cloud2.create_cloud(header, fields, [(*b[0], 100.0 + i) for i, b in enumerate(beams)])
    pair.echo2 = point_cloud2.create_cloud(header, fields, [(*b[1], 50.0 + i) for i, b in enumerate(beams)])
    pair.echo1.height, pair.echo1.width = 5, 6
    pair.echo1.row_step = 6 * pair.echo1.point_step
    return pair


def dual_return_cloud(header):
    fields = [PointField('x', 0, PointField.FLOAT32, 1), PointField('y', 4, PointField.FLOAT32, 1),
              PointField('z', 8, PointField.FLOAT32, 1), PointField('intensity', 12, PointField.FLOAT32, 1),
              PointField('return_type', 16, PointField.UINT8, 1), PointField('ring', 18, PointField.UINT16, 1)]
    points = []
    for i, (e1, e2) in enumerate(scene_beams()):
        ring = i // 6
        for k, p in enumerate((e1, e2)):
            points.append((*p, 10.0 * k + 1.0, k + 1, ring))
    return point_cloud2.create_cloud(header, fields, points)


def legacy_message(header):
    classes = legacy_classes()
    coord_dist, coord, dist = (classes['ohm_hokuyo3d/' + t] for t in ('CoordDist', 'Coord', 'Dist'))
    msg = classes[LEGACY_TYPE]()
    beams = scene_beams()
    import numpy as np
    for k in range(2):
        points = np.array([b[k] for b in beams], np.float32)
        mask = np.isfinite(points).all(axis=1)
        points[~mask] = 0.0
        n = len(beams)
        c = coord(header=header, fragmentid=0, fragmentsize=1, coords=points.ravel(),
                  normals=np.zeros(3 * n, np.float32), mask=mask.astype(np.uint8),
                  intensity=np.full(n, 10.0 + k, np.float32), objectType=np.zeros(n, np.int32))
        d = dist(header=header, dists=np.linalg.norm(points, axis=1).astype(np.float32),
                 phi=np.zeros(5, np.float32), mask=mask.astype(np.uint8))
        msg.coorddist.append(coord_dist(coord=c, dist=d))
    return msg


def multi_echo_scans():
    """Scans of frame 'laser' 0.02 s apart (a sweep every 0.05 s in the fuzzer): 12 beams with
    one or two echoes each, a discontinuity in the middle."""
    data = b''
    for s in range(4):
        scan = MultiEchoLaserScan()
        scan.header = Header(seq=s, stamp=rospy.Time.from_sec(100.0 + 0.02 * s), frame_id='laser')
        scan.angle_min, scan.angle_increment = -0.6, 0.1
        scan.angle_max = scan.angle_min + 11 * scan.angle_increment
        scan.time_increment, scan.scan_time = 0.001, 0.02
        scan.range_min, scan.range_max = 0.02, 30.0
        ranges = [[2.0] if i < 4 or i > 7 else [1.5, 3.0 + 0.1 * s] for i in range(12)]
        scan.ranges = [LaserEcho(echoes=r) for r in ranges]
        scan.intensities = [LaserEcho(echoes=[100.0] * len(r)) for r in ranges]
        body = serialize(scan)
        data += struct.pack('<I', len(body)) + body
    return data


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    header = Header(seq=1, stamp=rospy.Time(100, 5), frame_id='laser')
    bodies = {
        'pair': serialize(echo_pair(header)),
        'two_topics': serialize(echo_pair(header)),
        'dual_return': serialize(dual_return_cloud(header)),
        'hokuyo3d_legacy': serialize(legacy_message(header)),
        'multi_echo_scan': multi_echo_scans(),
    }
    for mode, body in bodies.items():
        for param_set in range(3):
            path = os.path.join(out_dir, 'seed_%s_params%d' % (mode, param_set))
            with open(path, 'wb') as f:
                f.write(bytes([MODES[mode], param_set]) + body)
            print('%s: %d bytes' % (path, 2 + len(body)))


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), 'corpus'))
