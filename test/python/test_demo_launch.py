"""demo.launch, as `make demo` runs it: the simulated experiment through the nodelet, scored by
the evaluator; with rviz:=true under Xvfb, rviz (rviz/prefilter.rviz) shows it and a screenshot is
saved, which must show the label colours (not a blank or error window).

The rviz test is skipped only when Xvfb is not installed. Needs the built package
(source .ws/devel/setup.bash); each run gets a master of its own on a free port.
"""
import json
import os
import shutil
import socket
import subprocess

import numpy as np
import pytest

from ohm_mirror_detector3d.label_colours import colour_8bit
from ohm_mirror_detector3d.labels import Label

# rviz draws points unlit, so their pixels carry the exact colour; a little slack for blending.
TOLERANCE = 12


def free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def roslaunch(prefix, args, timeout):
    """Runs demo.launch with `args` (behind `prefix`, e.g. xvfb-run); returns (exit code, log)."""
    pytest.importorskip('ohm_mirror_detector3d.msg')
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port)
    command = prefix + ['roslaunch', '-p', str(port), 'ohm_mirror_detector3d', 'demo.launch'] + args
    try:
        process = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 universal_newlines=True, timeout=timeout)
        return process.returncode, process.stdout
    except subprocess.TimeoutExpired as error:
        return None, error.stdout.decode() if isinstance(error.stdout, bytes) else (error.stdout or '')


def test_demo_scores_the_experiment_and_ends(tmp_path):
    # Coarser than make demo's 400 scans: this checks the launch file, not the accuracy.
    code, log = roslaunch([], ['scans:=100', 'out:=%s' % tmp_path], timeout=180)
    assert code == 0, log[-4000:]
    summary = json.loads((tmp_path / 'evaluation.json').read_text())
    assert summary, log[-4000:]
    for figure in ('labelled.png', 'cleaned.png', 'ground_truth.png'):
        assert (tmp_path / figure).exists(), figure
    assert 'ERROR' not in log and 'FATAL' not in log, log[-4000:]


@pytest.fixture(scope='module')
def screenshot(tmp_path_factory):
    if not (shutil.which('xvfb-run') and shutil.which('Xvfb')):
        pytest.skip('Xvfb is not installed (apt-get install xvfb xauth)')
    out = tmp_path_factory.mktemp('rviz_demo')
    shot = out / 'rviz.png'
    code, log = roslaunch(['xvfb-run', '-a', '-s', '-screen 0 1024x768x24'],
                          ['scans:=200', 'out:=%s' % out, 'rviz:=true', 'screenshot:=%s' % shot], timeout=240)
    assert shot.exists(), 'no screenshot (exit code %s); roslaunch said:\n%s' % (code, log[-4000:])
    assert (out / 'evaluation.json').exists(), 'the evaluator wrote nothing:\n' + log[-4000:]
    import matplotlib.image
    image = matplotlib.image.imread(str(shot))
    return (np.asarray(image)[..., :3] * 255).round().astype(int)


def pixels_of(image, label):
    colour = np.array(colour_8bit(label))
    return int(np.sum(np.all(np.abs(image - colour) <= TOLERANCE, axis=-1)))


def test_rviz_shows_valid_points_in_green(screenshot):
    assert pixels_of(screenshot, Label.VALID) > 2000


def test_rviz_shows_the_mirror_surface_in_turquoise_and_its_phantoms_in_orange(screenshot):
    assert pixels_of(screenshot, Label.REFLECTIVE_SURFACE) > 20
    assert pixels_of(screenshot, Label.BEHIND_REFLECTIVE) > 20
