"""The labelled cloud in the paper's colours, for rviz: an `rgb` field per point.

The pre-filter's `labelled` carries the label as a number; rviz can colour a cloud by a
numeric field only along a gradient, not by class. So the viewer (scripts/colour_labels)
republishes it with a packed `rgb` field that rviz's RGB8 colour transformer shows as is.
"""
import numpy as np

from .labels import LABEL_COLOURS, Label

# Packed 0x00RRGGBB of every label value (index = label), as rviz's `rgb` float32 field expects.
_PACKED = np.zeros(256, np.uint32)
for _label, (_r, _g, _b) in LABEL_COLOURS.items():
    _PACKED[int(_label)] = (int(round(_r * 255)) << 16) | (int(round(_g * 255)) << 8) | int(round(_b * 255))

COLOURED_DTYPE = np.dtype([('x', np.float32), ('y', np.float32), ('z', np.float32), ('rgb', np.float32),
                           ('label', np.uint8), ('echo', np.uint8)])


def colour_8bit(label):
    """The (r, g, b) 0..255 of a label as rviz draws it."""
    packed = int(_PACKED[int(label)])
    return (packed >> 16) & 0xFF, (packed >> 8) & 0xFF, packed & 0xFF


def coloured_points(points):
    """x y z rgb label echo of the finite points of a labelled structured array.

    Non-finite points (nanPoint beams without a measurement) are left out: rviz would skip them.
    """
    finite = np.isfinite(points['x']) & np.isfinite(points['y']) & np.isfinite(points['z'])
    points = points[finite]
    out = np.empty(len(points), COLOURED_DTYPE)
    for name in ('x', 'y', 'z', 'label', 'echo'):
        out[name] = points[name]
    out['rgb'] = _PACKED[points['label'].astype(np.intp)].view(np.float32)
    return out


def legend():
    """(label name, (r, g, b)) for the labels a user sees, in the order of the README's legend."""
    return [(label.design_name, colour_8bit(label)) for label in Label]
