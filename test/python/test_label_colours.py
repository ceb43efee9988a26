"""label_colours: the rgb field rviz shows for the labelled cloud."""
import numpy as np

from ohm_mirror_detector3d.label_colours import coloured_points, colour_8bit
from ohm_mirror_detector3d.labels import Label


def labelled(labels, xs=None):
    points = np.zeros(len(labels), [('x', np.float32), ('y', np.float32), ('z', np.float32), ('label', np.uint8),
                                    ('echo', np.uint8)])
    points['label'] = labels
    points['x'] = np.arange(len(labels)) if xs is None else xs
    points['echo'] = 1
    return points


def unpack(rgb):
    packed = np.asarray(rgb, np.float32).view(np.uint32)
    return np.stack([(packed >> 16) & 0xFF, (packed >> 8) & 0xFF, packed & 0xFF], axis=1)


def test_the_paper_colours_valid_green_surface_turquoise_behind_orange():
    out = coloured_points(labelled([Label.VALID, Label.REFLECTIVE_SURFACE, Label.BEHIND_REFLECTIVE,
                                    Label.TRANSPARENT_SURFACE, Label.BEHIND_TRANSPARENT]))
    rgb = unpack(out['rgb'])
    green, turquoise, orange = rgb[0], rgb[1], rgb[2]
    assert green[1] > 150 and green[0] < 60 and green[2] < 60
    assert turquoise[1] > 200 and turquoise[2] > 180 and turquoise[0] < 100
    assert orange[0] == 255 and 100 < orange[1] < 180 and orange[2] == 0
    np.testing.assert_array_equal(rgb[3], turquoise)
    np.testing.assert_array_equal(rgb[4], orange)
    assert tuple(green) == colour_8bit(Label.VALID)


def test_keeps_position_label_and_echo_and_drops_points_without_a_measurement():
    out = coloured_points(labelled([Label.VALID, Label.NAN_POINT, Label.ERROR], xs=[1.0, np.nan, 3.0]))
    np.testing.assert_array_equal(out['x'], [1.0, 3.0])
    np.testing.assert_array_equal(out['label'], [Label.VALID, Label.ERROR])
    np.testing.assert_array_equal(out['echo'], [1, 1])
