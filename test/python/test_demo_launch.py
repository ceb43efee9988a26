"""demo.launch, as `make demo` runs it: the simulated experiment through the nodelet, scored by
the evaluator; with rviz:=true under Xvfb, rviz (rviz/prefilter.rviz) shows it and a screenshot is
saved, which must show the label colours (not a blank or error window). Either way every process
of the launch (master and rosout too) must exit with 0: roslaunch's log says how each one ended.

The rviz test is skipped only when Xvfb is not installed. Needs the built package
(source .ws/devel/setup.bash); each run gets a master of its own on a free port.
"""
import glob
import json
import os
import re
import shutil
import socket
import subprocess
import warnings

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


def debug_logging_config(path):
    """ROS's Python logging configuration with roslaunch's own log at DEBUG, where it also
    records the exit code of a process that ended just before the launch stopped it."""
    import rospkg
    with open(os.path.join(rospkg.get_etc_ros_dir(), 'python_logging.conf')) as default:
        config, changed = re.subn(r'(\[logger_root\]\s*level\s*=\s*)\w+', r'\1DEBUG', default.read())
    assert changed == 1, 'no root logger level in ROS\'s python_logging.conf'
    path.write_text(config)
    return str(path)


def roslaunch(prefix, args, timeout, log_dir):
    """Runs demo.launch with `args` (behind `prefix`, e.g. xvfb-run), ROS logs in `log_dir`;
    returns (exit code, output)."""
    pytest.importorskip('ohm_mirror_detector3d.msg')
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port, ROS_LOG_DIR=str(log_dir),
               ROS_PYTHON_LOG_CONFIG_FILE=debug_logging_config(log_dir / 'python_logging.conf'))
    command = prefix + ['roslaunch', '-p', str(port), 'ohm_mirror_detector3d', 'demo.launch'] + args
    try:
        process = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 universal_newlines=True, timeout=timeout)
        return process.returncode, process.stdout
    except subprocess.TimeoutExpired as error:
        return None, error.stdout.decode() if isinstance(error.stdout, bytes) else (error.stdout or '')


# How roslaunch's log reports the end of a process: by itself (its process monitor), or when the
# launch stopped it (SIGINT, escalated to SIGTERM if it did not end, or already ended by then).
EXIT_REPORTS = (
    (r'\[([^\]\s]+)\] process has finished cleanly', lambda code: 0),
    (r'REQUIRED process \[([^\]]+)\] has died!\s*process has finished cleanly', lambda code: 0),
    (r'\[([^\]\s]+)\] process has died \[pid \d+, exit code (-?\d+)', int),
    (r'REQUIRED process \[([^\]]+)\] has died!\s*process has died \[pid \d+, exit code (-?\d+)', int),
    (r'process\[([^\]]+)\]: SIGINT killed with return value (-?\d+)', int),
    (r'process\[([^\]]+)\]: SIGTERM killed with return value (-?\d+)', lambda code: 'SIGTERM, then %s' % code),
    (r'process\[([^\]]+)\]: sent SIGKILL', lambda code: 'SIGKILL'),
    (r'process\[([^\]]+)\]\.stop\(\): process has already returned (-?\d+)', int),
)


def process_exits(log_dir):
    """{process name: exit code (or how it was killed)} of every process roslaunch started,
    None for one whose end it never reported, from roslaunch's log in `log_dir`."""
    logs = glob.glob(os.path.join(str(log_dir), '*', 'roslaunch-*.log'))
    assert logs, 'roslaunch wrote no log in %s' % log_dir
    text = ''
    for log in logs:
        with open(log) as f:
            text += f.read()
    exits = {name: None for name in re.findall(r'process\[([^\]]+)\]: start w/ args', text)}
    for pattern, code_of in EXIT_REPORTS:
        for match in re.finditer(pattern, text):
            name = match.group(1)
            code = code_of(match.group(2) if match.lastindex > 1 else None)
            if exits.get(name) in (None, 0):
                exits[name] = code
    return exits


def assert_every_process_exited_0(log_dir, output):
    exits = process_exits(log_dir)
    assert {'master', 'rosout-1'} < set(exits), exits
    assert all(code == 0 for code in exits.values()), '%s\n%s' % (exits, output[-4000:])


def test_demo_scores_the_experiment_and_ends(tmp_path):
    # Coarser than make demo's 400 scans: this checks the launch file, not the accuracy.
    log_dir = tmp_path / 'log'
    log_dir.mkdir()
    code, log = roslaunch([], ['scans:=100', 'out:=%s' % tmp_path], timeout=180, log_dir=log_dir)
    assert code == 0, log[-4000:]
    assert_every_process_exited_0(log_dir, log)
    summary = json.loads((tmp_path / 'evaluation.json').read_text())
    assert summary, log[-4000:]
    for figure in ('labelled.png', 'cleaned.png', 'ground_truth.png'):
        assert (tmp_path / figure).exists(), figure
    assert 'ERROR' not in log and 'FATAL' not in log, log[-4000:]


# How Debian's rviz 1.14 on Mesa's software GL (llvmpipe, under Xvfb) dies on its own, not of
# anything the demo sends it: a segmentation fault, or glibc's heap check aborting it. It does so
# while drawing in about 2 of 15 runs here (stop 38), before the screenshot, which then shows no
# labels (README, Troubleshooting).
RVIZ_CRASH_CODES = (-11, -6)


def rviz_alone_crashed(exits):
    """Whether, by `exits` (process_exits), rviz ended by a crash of its own and every other process
    of the launch with 0, but rviz_screenshot, which then had no rviz to take a picture of."""
    rviz = [code for name, code in exits.items() if re.fullmatch(r'rviz-\d+', name)]
    others = [code for name, code in exits.items() if not re.fullmatch(r'rviz(_screenshot)?-\d+', name)]
    return bool(rviz) and all(code in RVIZ_CRASH_CODES for code in rviz) and all(code == 0 for code in others)


@pytest.fixture(scope='module')
def screenshot(tmp_path_factory):
    if not (shutil.which('xvfb-run') and shutil.which('Xvfb')):
        pytest.skip('Xvfb is not installed (apt-get install xvfb xauth)')
    # One more run when rviz alone crashed in the first (RVIZ_CRASH_CODES), saying so: a crash of
    # rviz in both runs, or any other failure, still fails the tests below.
    for attempt in (1, 2):
        out = tmp_path_factory.mktemp('rviz_demo')
        shot = out / 'rviz.png'
        log_dir = out / 'log'
        log_dir.mkdir()
        code, log = roslaunch(['xvfb-run', '-a', '-s', '-screen 0 1024x768x24'],
                              ['scans:=200', 'out:=%s' % out, 'rviz:=true', 'screenshot:=%s' % shot], timeout=240,
                              log_dir=log_dir)
        exits = process_exits(log_dir) if attempt == 1 else None
        if exits is not None and rviz_alone_crashed(exits):
            warnings.warn('rviz crashed on its own in the first run of the demo (%s); running it again. '
                          'Its output:\n%s' % (exits, log[-2000:]))
            continue
        break
    assert shot.exists(), 'no screenshot (exit code %s); roslaunch said:\n%s' % (code, log[-4000:])
    assert (out / 'evaluation.json').exists(), 'the evaluator wrote nothing:\n' + log[-4000:]
    import matplotlib.image
    image = matplotlib.image.imread(str(shot))
    return RvizDemo((np.asarray(image)[..., :3] * 255).round().astype(int), code, log, log_dir)


class RvizDemo:
    def __init__(self, image, code, output, log_dir):
        self.image, self.code, self.output, self.log_dir = image, code, output, log_dir


def test_rviz_demo_ends_with_every_process_exiting_0(screenshot):
    # rviz on Mesa's software GL crashes (SIGSEGV, or SIGABRT after glibc's "corrupted size vs.
    # prev_size") when the launch's shutdown reaches it while it draws line markers; the demo
    # quits it with Ctrl+Q before it ends.
    assert screenshot.code == 0, screenshot.output[-4000:]
    assert_every_process_exited_0(screenshot.log_dir, screenshot.output)
    assert 'rviz_screenshot: rviz has quit' in screenshot.output, screenshot.output[-4000:]


def pixels_of(image, label):
    colour = np.array(colour_8bit(label))
    return int(np.sum(np.all(np.abs(image - colour) <= TOLERANCE, axis=-1)))


def test_rviz_shows_valid_points_in_green(screenshot):
    assert pixels_of(screenshot.image, Label.VALID) > 2000


def test_rviz_shows_the_mirror_surface_in_turquoise_and_its_phantoms_in_orange(screenshot):
    assert pixels_of(screenshot.image, Label.REFLECTIVE_SURFACE) > 20
    assert pixels_of(screenshot.image, Label.BEHIND_REFLECTIVE) > 20
