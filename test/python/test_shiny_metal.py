"""Shiny metal that the geometry of its points behind cannot type (stop 42: took for glass) is a
mirror by its echoes:
lit like a wall off its specular peak, each echo with a reflection behind it
(intensity_evidence.h: diffuseReflector). Random scene 6013 of the 64-ring lidar: a 102 x 105 cm
metal panel whose reflections land on the hidden faces of what stands in front of it or beside
what the sensor saw, and a mirror that the geometry types alone.
"""
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402

MIRROR = 1
FAMILY = 'hesai_qt64'


@pytest.fixture(scope='module')
def sweep(evaluation_sweep):
    return evaluation_sweep(FAMILY, 'random_6013')


def run(sweep, **params):
    """{truth name: detected object} and the evaluator's counts of the sweep through a pipeline."""
    return ev.found_objects(core.Pipeline(**params), sweep, FAMILY)


def test_shiny_metal_the_geometry_takes_for_glass_is_a_mirror_by_its_diffuse_echoes(sweep):
    found, counts = run(sweep)
    metal = found['metal_0']
    assert metal['type'] == MIRROR
    assert metal['intensity_diffuse_reflector'] and not metal['intensity_typed']
    # What made it: nearly all its echoes off the peak bright, backed by a reflection, and a
    # surface echo in front of nearly every point behind its inside.
    assert metal['intensity_bright_off_peak'] >= 0.9 * metal['intensity_off_peak'] >= 20
    assert metal['intensity_bright_backed_share'] >= 0.85
    assert metal['surface_backed_share'] >= 0.9
    # The mirror is the geometry's: the rule is not what types it.
    assert found['mirror_0']['type'] == MIRROR and not found['mirror_0']['intensity_diffuse_reflector']

    # Without the intensities the geometry alone cannot tell (its reflections land on the hidden
    # faces of what stands in front, occluded), and the panel's reflections stay.
    off, counts_off = run(sweep, intensity_evidence=0)
    assert off['metal_0']['type'] != MIRROR
    assert counts['double_echo_phantoms_wrong_place'] + 100 < counts_off['double_echo_phantoms_wrong_place']
    assert counts['real_displaced'] <= counts_off['real_displaced']
