"""Every named scene synthesises with sensible counts; the paper's experiments look like the paper's,
under both physics models."""
import numpy as np
import pytest

from ohm_mirror_detector3d import scene, simulate
from ohm_mirror_detector3d.labels import Label
from ohm_mirror_detector3d.physics import PhysicsParams
from ohm_mirror_detector3d.scanner import RotatingHokuyo

MODELS = [PhysicsParams.ideal(), PhysicsParams()]

REQUIRED = ['experiment1', 'experiment2', 'experiment3', 'experiment4', 'empty_room', 'glass_wall',
            'facing_mirrors', 'floor_mirror', 'mirror_and_glass', 'mirror_open_space',
            'two_mirrors_and_glass', 'facing_tall_mirrors', 'wall_mirror', 'pane_in_wall', 'office', 'doorway_room']


def test_registry_lists_the_required_scenes():
    assert set(REQUIRED) <= set(scene.names())
    with pytest.raises(KeyError):
        scene.get('no_such_scene')
    assert all(desc for _, desc in scene.describe())


@pytest.mark.parametrize('physics', MODELS, ids=lambda p: p.model)
@pytest.mark.parametrize('name', REQUIRED)
def test_scene_synthesises_with_sensible_counts(name, physics):
    sweep = simulate.simulate_sweep(name, RotatingHokuyo(scans=100), seed=0, physics=physics)
    counts = sweep.counts()
    assert counts['beams'] == 108000
    assert counts['beams_with_return'] > 0.25 * counts['beams']
    objects = sweep.objects
    mirrors = [o for o in counts['objects'] if o['type'] == scene.OBJECT_TYPE_MIRROR]
    panes = [o for o in counts['objects'] if o['type'] == scene.OBJECT_TYPE_GLASS]
    if name == 'empty_room':
        assert not objects and set(counts['labels']) <= {'valid', 'nan_point'}
    if name != 'mirror_open_space':
        for m in mirrors:
            assert m['phantoms'] > 20, m  # real scene in front of every mirror
    else:
        assert mirrors[0]['surface'] > 100 and mirrors[0]['phantoms'] < mirrors[0]['surface'] / 2
    for p in panes:
        assert p['behind_glass'] > 100, p
    if name != 'floor_mirror':  # a mirror lying on the floor is seen too obliquely for surface echoes
        assert sum(o['surface'] for o in counts['objects']) > 0 or not objects
    # Object geometry: planes face the sensor, corners lie on them, width along the horizontal side.
    for o in sweep.objects:
        plane = o['plane']
        assert plane[3] > 0 and np.isclose(np.linalg.norm(plane[:3]), 1.0)
        np.testing.assert_allclose(o['corners'] @ plane[:3] + plane[3], 0, atol=1e-9)
        c = o['corners']
        sides = sorted([np.linalg.norm(c[1] - c[0]), np.linalg.norm(c[3] - c[0])])
        assert np.isclose(sorted([o['width'], o['height']]), sides).all()


@pytest.mark.parametrize('physics', MODELS, ids=lambda p: p.model)
def test_experiment1_mirror_gives_double_echoes_over_its_whole_surface(physics):
    sweep = simulate.simulate_sweep('experiment1', RotatingHokuyo(scans=400), seed=0, physics=physics)
    obj = sweep.objects[0]
    assert (obj['width'], obj['height']) == (0.6, 0.4)
    counts = sweep.counts()['objects'][0]
    assert counts['surface'] == counts['surface_double_echo'] > 800
    if physics.ideal_model:
        assert counts['phantoms'] == counts['surface']
    else:
        # Beams whose footprint straddles the mirror's edge see a phantom without a surface echo.
        assert counts['surface'] <= counts['phantoms'] < 1.1 * counts['surface']
    gt = sweep.ground_truth
    n = sweep.num_beams
    surf = gt[:n][gt['label'][:n] == Label.REFLECTIVE_SURFACE]
    c = obj['corners']
    u, v = (c[1] - c[0]) / np.linalg.norm(c[1] - c[0]), (c[3] - c[0]) / np.linalg.norm(c[3] - c[0])
    p = simulate.xyz(surf)
    extents = sorted([np.ptp(p @ u), np.ptp(p @ v)])
    np.testing.assert_allclose(extents, [0.4, 0.6], atol=0.03)


@pytest.mark.parametrize('physics', MODELS, ids=lambda p: p.model)
def test_experiment2_glass_returns_surface_echoes_only_in_a_small_patch(physics):
    sweep = simulate.simulate_sweep('experiment2', RotatingHokuyo(scans=400), seed=0, physics=physics)
    gt = sweep.ground_truth
    n = sweep.num_beams
    surf = gt[:n][gt['label'][:n] == Label.TRANSPARENT_SURFACE]
    assert 200 < len(surf) < 1000
    p = simulate.xyz(surf)
    obj = sweep.objects[surf['object_id'][0]]
    assert sorted([obj['width'], obj['height']]) == [0.88, 1.98]
    c = obj['corners']
    u, v = (c[1] - c[0]) / np.linalg.norm(c[1] - c[0]), (c[3] - c[0]) / np.linalg.norm(c[3] - c[0])
    for extent in (np.ptp(p @ u), np.ptp(p @ v)):
        assert 0.2 < extent < 0.4  # the paper: 31 x 24 cm of an 88 x 198 cm pane
    assert (gt['label'] == Label.BEHIND_TRANSPARENT).sum() > 10 * len(surf)


def test_horizontal_object_width_is_the_longer_side():
    sweep = simulate.simulate_sweep('floor_mirror', RotatingHokuyo(scans=20), seed=0)
    assert (sweep.objects[0]['width'], sweep.objects[0]['height']) == (0.6, 0.4)
