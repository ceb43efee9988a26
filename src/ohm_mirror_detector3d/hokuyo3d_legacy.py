"""A simulated sweep as the original driver's tuple message ohm_hokuyo3d/CoordDistMulti (input mode
hokuyo3d_legacy), without that package: the message class is generated at run time from its
definition (genpy.dynamic), so a rospy publisher sends the same definition a real driver would.

Layout (as far as known, and as the pre-filter decodes it by field name):
coorddist[0] is echo 1, coorddist[1] echo 2; per echo a Coord (header, fragment id/size,
coords 3N, normals 3N, mask N, intensity N, objectType N) and a Dist (header, dists N,
phi, mask N). Point i of both echoes is beam i of the sweep (row-major); a beam without
return has mask false and zeros as coordinates (the mask, not NaN, says it is empty). As in
the EchoPair, a single-return beam repeats its return in echo 2, so the sweep's own ground
truth (simulate.Sweep.ground_truth) applies unchanged.
"""
import numpy as np

from .simulate import xyz

LEGACY_TYPE = 'ohm_hokuyo3d/CoordDistMulti'
_LINE = '=' * 80 + '\n'
HEADER_DEFINITION = 'uint32 seq\ntime stamp\nstring frame_id\n'
COORD_FIELDS = ('Header header\nuint32 fragmentid\nuint32 fragmentsize\nfloat32[] coords\nfloat32[] normals\n'
                'bool[] mask\nfloat32[] intensity\nint32[] objectType\n')


def legacy_definition(coord_fields=COORD_FIELDS):
    """The full message definition text (main message, then the MSG: sections), as a publisher sends it."""
    return ('CoordDist[] coorddist\n' + _LINE + 'MSG: ohm_hokuyo3d/CoordDist\nCoord coord\nDist dist\n' + _LINE
            + 'MSG: ohm_hokuyo3d/Coord\n' + coord_fields + _LINE + 'MSG: std_msgs/Header\n' + HEADER_DEFINITION
            + _LINE + 'MSG: ohm_hokuyo3d/Dist\nHeader header\nfloat32[] dists\nfloat32[] phi\nbool[] mask\n')


def legacy_classes(definition=None):
    """{type name: generated class} for the legacy message and its nested types (numpy-serialising)."""
    import genpy.dynamic
    from rospy.numpy_msg import numpy_msg
    classes = genpy.dynamic.generate_dynamic(LEGACY_TYPE, definition or legacy_definition())
    classes[LEGACY_TYPE] = numpy_msg(classes[LEGACY_TYPE])
    return classes


def legacy_message(sweep, header, classes=None):
    """A CoordDistMulti of the sweep (both echoes), every header a copy of `header`."""
    import copy
    classes = classes or legacy_classes()
    coord_dist, coord, dist = (classes['ohm_hokuyo3d/' + t] for t in ('CoordDist', 'Coord', 'Dist'))
    msg = classes[LEGACY_TYPE]()
    n = sweep.num_beams
    for echo in (sweep.echo1, sweep.echo2):
        points = xyz(echo)
        mask = np.isfinite(points).all(axis=1)
        coords = np.where(mask[:, None], points, 0.0).astype(np.float32).ravel()
        intensity = np.where(mask, echo['intensity'], 0.0).astype(np.float32)
        ranges = np.where(mask, np.linalg.norm(np.nan_to_num(points), axis=1), 0.0).astype(np.float32)
        c = coord(header=copy.deepcopy(header), fragmentid=0, fragmentsize=1, coords=coords,
                  normals=np.zeros(3 * n, np.float32), mask=mask.astype(np.uint8), intensity=intensity,
                  objectType=np.zeros(n, np.int32))
        d = dist(header=copy.deepcopy(header), dists=ranges, phi=np.zeros(sweep.rows, np.float32),
                 mask=mask.astype(np.uint8))
        msg.coorddist.append(coord_dist(coord=c, dist=d))
    return msg


TOPIC_COORD_DIST = 'coord_dist'


def legacy_messages(sweep, stamp, frame_id=None, classes=None):
    """Messages of one sweep keyed by topic: coord_dist (the legacy message), ground_truth and
    ground_truth_objects (those of the EchoPair format: the beam layout is the same)."""
    from . import ros_io
    header = ros_io.make_header(stamp, frame_id or sweep.frame_id)
    messages = ros_io.sweep_to_messages(sweep, stamp, frame_id)
    return {
        TOPIC_COORD_DIST: legacy_message(sweep, header, classes),
        ros_io.TOPIC_GROUND_TRUTH: messages[ros_io.TOPIC_GROUND_TRUTH],
        ros_io.TOPIC_GROUND_TRUTH_OBJECTS: messages[ros_io.TOPIC_GROUND_TRUTH_OBJECTS],
    }
