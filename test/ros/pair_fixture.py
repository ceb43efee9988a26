"""A hand-made EchoPair whose right labels are obvious, shared by the rostest checkers."""
import math

import numpy as np
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointField

from ohm_mirror_detector3d.labels import Label
from ohm_mirror_detector3d.msg import EchoPair

NAN = float('nan')

# (echo1, echo2) per beam, in metres straight ahead, and the labels expected of them. Too few
# discontinuous beams for an object: their near echo is kept as valid, the far one dropped.
BEAMS = [
    ((2.0, 0.0, 0.0), (3.5, 0.0, 0.0), Label.VALID, Label.ERROR),            # discontinuous beam
    ((3.5, 0.1, 0.0), (2.0, 0.1, 0.0), Label.ERROR, Label.VALID),            # same, echoes swapped
    ((4.0, 0.2, 0.0), (4.0, 0.2, 0.0), Label.VALID, Label.VALID),            # single return, repeated
    ((5.0, 0.3, 0.0), (NAN, NAN, NAN), Label.VALID, Label.NAN_POINT),        # single return, NaN echo 2
    ((math.inf, 0.0, 0.0), (-math.inf, 0.0, 0.0), Label.NAN_POINT, Label.NAN_POINT),  # REP-117 +-Inf
    ((70.0, 0.0, 0.0), (0.01, 0.0, 0.0), Label.NAN_POINT, Label.NAN_POINT),  # beyond d_max, before d_min
    ((6.0, 0.0, 1.0), (6.02, 0.0, 1.0), Label.VALID, Label.VALID),           # echoes agree within d_thres
]

FIELDS = [PointField(name, 4 * i, PointField.FLOAT32, 1) for i, name in enumerate(('x', 'y', 'z', 'intensity'))]


def make_pair(header, threshold_beam=None):
    """The fixture as an EchoPair (1 x N clouds, intensity = 10 * beam + echo)."""
    echo1 = [(*b[0], 10.0 * i + 1) for i, b in enumerate(BEAMS)]
    echo2 = [(*b[1], 10.0 * i + 2) for i, b in enumerate(BEAMS)]
    pair = EchoPair(header=header)
    pair.echo1 = point_cloud2.create_cloud(header, FIELDS, echo1)
    pair.echo2 = point_cloud2.create_cloud(header, FIELDS, echo2)
    return pair


def read_output(cloud):
    """A structured numpy array of an output cloud (labelled or cleaned)."""
    names = ('x', 'y', 'z', 'intensity', 'label', 'echo', 'beam')
    dtype = [('x', np.float32), ('y', np.float32), ('z', np.float32), ('intensity', np.float32),
             ('label', np.uint8), ('echo', np.uint8), ('beam', np.uint32)]
    return np.array(list(point_cloud2.read_points(cloud, field_names=names)), dtype=dtype)
