"""scripts/calibrate_intensity on simulated bags of a driving lidar with the scenes' mirrors and panes as the
known objects (in odom, the bags' /tf giving each sweep's pose): the fitted model separates mirror from
glass, is a parameter file the pre-filter accepts, and the same sweeps as one dual-return cloud give the
same features; bad object files give a clear error."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest
import yaml

from ohm_mirror_detector3d import core, ros_io
from ohm_mirror_detector3d import intensity_features as features
from ohm_mirror_detector3d import scanner as scanners
from ohm_mirror_detector3d import scene as scenes
from ohm_mirror_detector3d.dual_return_cloud import dual_return_messages
from ohm_mirror_detector3d.sensor_path import scene_path
from ohm_mirror_detector3d.simulate import SweepSimulator

SCRIPT = os.path.join(os.path.dirname(__file__), '..', '..', 'scripts', 'calibrate_intensity')
SCENES = ('wall_mirror', 'experiment1', 'pane_in_wall', 'glass_wall')
SWEEPS = 2
SENSOR = 'velodyne_hdl32e'   # 2250 columns: 0.16 deg
RESOLUTION = 360.0 / 2250


def run(*args):
    return subprocess.run([sys.executable, SCRIPT] + [str(a) for a in args], capture_output=True, text=True,
                          timeout=600)


@pytest.fixture(scope='module')
def bags(tmp_path_factory):
    """Per scene: (pair bag, dual-return bag, objects file)."""
    root = tmp_path_factory.mktemp('calibration')
    out = {}
    for name in SCENES:
        scene = scenes.get(name)
        path = scene_path(scene, SWEEPS)
        simulator = SweepSimulator(scene, scanners.preset(SENSOR))
        sweeps = [simulator.sweep(seed=k, pose=pose) for k, pose in enumerate(path.poses)]
        pair, dual = root / (name + '.bag'), root / (name + '_dual.bag')
        ros_io.write_sweeps_bag(str(pair), sweeps, frame_id='lidar', sensor_path=path)
        ros_io.write_sweeps_bag(str(dual), sweeps, frame_id='lidar', sensor_path=path,
                                to_messages=lambda s, t, f: dual_return_messages(s, t, f))
        objects = root / (name + '.yaml')
        objects.write_text(yaml.safe_dump({'frame': 'odom', 'objects': [
            {'name': r.name, 'type': 'glass' if r.material.kind == scenes.GLASS else 'mirror',
             'corners': r.corners().tolist()} for r in scene.objects()]}))
        out[name] = (pair, dual, objects)
    return out


def test_fitted_model_separates_mirror_from_glass_and_is_a_parameter_file(bags, tmp_path):
    out = tmp_path / 'intensity.yaml'
    args = [out] + [p for name in SCENES for p in (bags[name][0], bags[name][2])]
    done = run(*args)
    assert done.returncode == 0, done.stderr
    params = core.Params.from_yaml(str(out))
    assert params.intensity_evidence == 1
    # The mirrors' faces are hazy, the panes' are not.
    assert params.intensity_faint_share_mirror > params.intensity_faint_share_glass + 0.5
    fitted = yaml.safe_load(out.read_text())
    assert {'intensity_faint_share_mirror', 'intensity_faint_share_glass', 'intensity_faint_share_sigma'} <= set(fitted)
    for feature in features.FEATURES:   # each feature says whether it was fitted or kept its default
        assert re.search(r'%s: \d+ mirror and \d+ glass sweeps with it: (fitted|kept at its default)' % feature,
                         done.stderr), done.stderr
    # On the training objects the log-odds point the right way.
    line = out.read_text().splitlines()[0]
    right, decided = map(int, re.search(r'(\d+) of the (\d+) with any evidence', line).groups())
    assert decided >= 2 * SWEEPS and right >= 0.8 * decided, line


def test_dual_return_cloud_gives_the_features_of_the_echo_pair(bags, tmp_path):
    pair, dual, objects = bags['wall_mirror']
    outs = []
    for bag, extra in ((pair, []), (dual, ['--input-mode', 'dual_return', '--azimuth-resolution-deg', RESOLUTION])):
        out = tmp_path / ('%s.yaml' % len(outs))
        done = run(out, bag, objects, pair.parent / 'pane_in_wall.bag' if not extra else
                   pair.parent / 'pane_in_wall_dual.bag', pair.parent / 'pane_in_wall.yaml', *extra)
        assert done.returncode == 0, done.stderr
        outs.append(yaml.safe_load(out.read_text()))
    assert set(outs[1]) == set(outs[0])
    for key in ('intensity_faint_share_mirror', 'intensity_faint_share_glass', 'intensity_echo_ratio_mirror'):
        assert outs[1][key] == pytest.approx(outs[0][key], abs=0.05), key


@pytest.mark.parametrize('content, says', [
    ('objects: []', 'needs a list'),
    ('objects: [{type: metal, corners: [[0,0,0],[1,0,0],[1,0,1],[0,0,1]]}]', 'type must be mirror or glass'),
    ('objects: [{type: glass, corners: [[0,0,0],[1,0,0]]}]', 'corners must be 4 points'),
    ('objects: [: bad', 'cannot read it'),
])
def test_bad_objects_file_is_refused_naming_the_problem(bags, tmp_path, content, says):
    bad = tmp_path / 'bad.yaml'
    bad.write_text(content)
    done = run(tmp_path / 'out.yaml', bags['wall_mirror'][0], bad)
    assert done.returncode == 2
    assert says in done.stderr
    assert not (tmp_path / 'out.yaml').exists()


def test_log_odds_follow_the_model():
    params = core.Params()
    mirror_like = {'haze': 10 ** params.intensity_haze_mirror, 'faint_share': params.intensity_faint_share_mirror,
                   'echo_ratio': float('nan')}
    glass_like = {'haze': float('nan'), 'faint_share': params.intensity_faint_share_glass,
                  'echo_ratio': float('nan')}
    assert features.log_odds(mirror_like, params) > params.intensity_type_log_odds
    assert features.log_odds(glass_like, params) < 0
    assert features.log_odds({'haze': float('nan')}, params) == 0.0
    assert abs(features.log_odds({'haze': 1e-9, 'faint_share': 0.0, 'echo_ratio': 1e-9}, params)) \
        <= features.MAX_LOG_ODDS
    fitted, counts = features.fit_model([('mirror', {'haze': 0.02}), ('mirror', {'haze': 0.03}),
                                         ('glass', {'haze': 0.002}), ('glass', {'haze': 0.003})])
    assert fitted['intensity_haze_mirror'] == pytest.approx(np.mean(np.log10([0.02, 0.03])))
    assert 'intensity_faint_share_mirror' not in fitted and counts['faint_share'] == {'mirror': 0, 'glass': 0}


def test_calibration_features_are_the_stages_own():
    """object_features on an object the pipeline found gives what the intensity_evidence stage stored on
    it: the calibration fits the model on exactly what the stage measures."""
    scene = scenes.get('wall_mirror')
    sweep = SweepSimulator(scene, scanners.preset('hokuyo_utm30lx_ew')).sweep(seed=3)
    result = core.Pipeline(intensity_evidence=1).filter(sweep.echo1, sweep.echo2)
    found = [o for o in result.objects if o['intensity_echoes'] >= 50]
    assert found, 'the wall mirror gives an object with intensity features'
    for obj in found:
        f = features.object_features(sweep.echo1, sweep.echo2, obj)
        assert f['echoes'] == obj['intensity_echoes'] and f['off_peak'] == obj['intensity_off_peak']
        for name in ('faint_share', 'haze', 'echo_ratio'):
            assert f[name] == pytest.approx(obj['intensity_' + name], nan_ok=True, rel=1e-6), name
