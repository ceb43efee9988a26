import numpy as np

from ohm_mirror_detector3d.example_sweep import MIRROR_DISTANCE, PHANTOM_EXTRA_RANGE, example_sweep
from ohm_mirror_detector3d.labels import KEPT_IN_CLEANED, Label


def test_mirror_beams_have_a_surface_echo_and_a_phantom_farther_along_the_same_ray():
    echo1, echo2, is_mirror = example_sweep(noise=0.0)
    range1 = np.linalg.norm(echo1[is_mirror], axis=-1)
    range2 = np.linalg.norm(echo2[is_mirror], axis=-1)
    np.testing.assert_allclose(echo1[is_mirror][:, 0], MIRROR_DISTANCE, atol=1e-5)
    np.testing.assert_allclose(range2 - range1, PHANTOM_EXTRA_RANGE, atol=1e-4)
    directions1 = echo1[is_mirror] / range1[:, None]
    directions2 = echo2[is_mirror] / range2[:, None]
    np.testing.assert_allclose(directions1, directions2, atol=1e-5)


def test_other_beams_repeat_their_single_return_and_the_top_row_has_none():
    echo1, echo2, is_mirror = example_sweep()
    single = ~is_mirror
    single[-1] = False
    np.testing.assert_array_equal(echo1[single], echo2[single])
    assert np.isnan(echo1[-1]).all() and np.isnan(echo2[-1]).all()
    assert 0 < is_mirror.sum() < is_mirror.size


def test_is_deterministic_under_a_seed():
    first = example_sweep(seed=3)[0]
    np.testing.assert_array_equal(first, example_sweep(seed=3)[0])
    assert not np.array_equal(first, example_sweep(seed=4)[0], equal_nan=True)


def test_label_values_match_the_design_contract():
    assert [int(label) for label in Label] == list(range(10))
    assert Label.ERROR not in KEPT_IN_CLEANED and Label.NAN_POINT not in KEPT_IN_CLEANED


def test_design_names_match_the_cpp_core():
    assert Label.ERROR_SURFACE.design_name == 'errorSurface'
    assert Label.BEHIND_ERROR_S.design_name == 'behindErrorS'
    assert Label.NAN_POINT.design_name == 'nanPoint'
