"""The phantom_planes object stage (src/core/phantom_planes.cpp) on a whole sweep, through the
Python bindings: an object made of another object's phantoms is removed, and its phantoms are put
right (back-projected across the plane of the object they are phantoms of).

Random scene 7 on the rotating Hokuyo (realistic physics, default parameters, the evaluation's own
case): with the stage, 5 objects fewer (11 instead of 16), 945 fewer double-echo phantoms left at
a wrong place, 432 fewer real points displaced and 13 fewer lost than with phantom_plane_share 0
(measured at stop 29).
"""
import dataclasses

import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import metrics  # noqa: E402
from ohm_mirror_detector3d import scene as scenes  # noqa: E402
from ohm_mirror_detector3d import scene_evaluation as ev  # noqa: E402
from ohm_mirror_detector3d.simulate import SweepSimulator, ground_truth_objects  # noqa: E402

FAMILY = 'hokuyo_utm30lx_ew'
SCENE = 'random_7'


def filtered(sweep, params):
    """(the evaluator's figures, the objects found) of the sweep through a pipeline of params."""
    ground_truth, labelled, cleaned, objects = ev.filter_case(core.Pipeline(params), sweep, ev.INPUT_MODES[FAMILY])
    return metrics.evaluate_sweep(ground_truth, labelled, cleaned, objects, ground_truth_objects(sweep)), objects


@pytest.fixture(scope='module')
def with_and_without():
    case = next(c for c in ev.cases([FAMILY], 8, 0, named=False) if c.scene == SCENE)
    sweep = SweepSimulator(scenes.get(case.scene), ev.scanner_of(case)).sweep(seed=case.seed)
    return filtered(sweep, core.Params()), filtered(sweep, dataclasses.replace(core.Params(), phantom_plane_share=0.0))


def test_the_default_switches_the_stage_on():
    assert core.Params().phantom_plane_share == 0.5


def test_a_phantom_plane_is_no_object(with_and_without):
    (_, objects_on), (_, objects_off) = with_and_without
    assert len(objects_on) < len(objects_off)


def test_its_phantoms_are_put_right(with_and_without):
    (on, _), (off, _) = with_and_without
    left_on = on['counts']['double_echo_phantoms_wrong_place']
    left_off = off['counts']['double_echo_phantoms_wrong_place']
    assert left_on <= left_off - 500, (left_on, left_off)
    # ... and the real points behind the phantom planes stay where they are.
    assert on['counts']['real_displaced'] <= off['counts']['real_displaced']
    assert on['counts']['real_lost'] <= off['counts']['real_lost']
