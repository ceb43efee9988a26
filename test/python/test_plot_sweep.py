"""scripts/plot_sweep on small hand-made bags: the pre-filter's output drawn before/after in the
paper's colours, an input-only bag drawn as its echoes, a clear error otherwise."""
import os
import subprocess
import sys

import numpy as np
import pytest

from ohm_mirror_detector3d.labels import LABEL_COLOURS, Label

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      'scripts', 'plot_sweep')
OUTPUT_DTYPE = [('x', np.float32), ('y', np.float32), ('z', np.float32), ('intensity', np.float32),
                ('label', np.uint8), ('echo', np.uint8), ('beam', np.uint32)]
# A mirror in the plane x = 2 (0.6 wide, 0.4 high).
MIRROR = {'id': 0, 'type': 1, 'corners': [[2, -0.3, 0.0], [2, 0.3, 0.0], [2, 0.3, 0.4], [2, -0.3, 0.4]],
          'width': 0.6, 'height': 0.4, 'plane': [-1.0, 0.0, 0.0, 2.0]}


def cloud(points, label):
    out = np.zeros(len(points), OUTPUT_DTYPE)
    out['x'], out['y'], out['z'] = np.asarray(points, np.float32).T
    out['label'] = label
    return out


def grid(x, y0, y1, z0, z1, n=30):
    y, z = np.meshgrid(np.linspace(y0, y1, n), np.linspace(z0, z1, n))
    return np.stack([np.full(y.size, x), y.ravel(), z.ravel()], axis=1)


def run(*args):
    return subprocess.run([sys.executable, SCRIPT] + [str(a) for a in args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, universal_newlines=True, timeout=120)


def colour_pixels(path, label):
    import matplotlib.image
    image = (matplotlib.image.imread(str(path))[..., :3] * 255).round()
    colour = np.array(LABEL_COLOURS[label]) * 255
    return int(np.sum(np.all(np.abs(image - colour) <= 10, axis=-1)))


@pytest.fixture(scope='module')
def output_bag(ros_messages, tmp_path_factory):
    import rosbag
    import rospy
    ros_io = ros_messages
    # A dense floor (seen in the top view) and dense patches, so that whole pixels take the colours.
    floor = grid(0.0, 0.5, 4.0, -2.0, 2.0, 150)[:, [1, 2, 0]] - [0, 0, 1.0]
    wall = cloud(floor, Label.VALID)
    surface = cloud(grid(2.0, -0.3, 0.3, 0.0, 0.4, 40) + [[0.02, 0, 0]] * np.linspace(-1, 1, 1600)[:, None],
                    Label.REFLECTIVE_SURFACE)
    phantoms = cloud(grid(3.0, -0.3, 0.3, 0.0, 0.4, 40) + [[0.3, 0, 0]] * np.linspace(-1, 1, 1600)[:, None],
                     Label.BEHIND_REFLECTIVE)
    labelled = np.concatenate([wall, surface, phantoms])
    back_projected = phantoms.copy()
    back_projected['x'] = 1.0  # reflected across x = 2
    cleaned = np.concatenate([wall, surface, back_projected])
    path = tmp_path_factory.mktemp('plot_sweep') / 'output.bag'
    with rosbag.Bag(str(path), 'w') as bag:
        for k in range(2):
            stamp = rospy.Time(100 + k)
            header = ros_io.make_header(stamp, 'laser')
            bag.write('/prefilter/labelled', ros_io.array_to_cloud(labelled, header), stamp)
            bag.write('/prefilter/cleaned', ros_io.array_to_cloud(cleaned, header), stamp)
            bag.write('/prefilter/objects', ros_io.objects_to_msg([MIRROR], header), stamp)
    return path


def test_draws_before_and_after_in_the_paper_colours(output_bag, tmp_path):
    png = tmp_path / 'sweep.png'
    p = run(output_bag, '--out', png, '--dpi', 80)
    assert p.returncode == 0, p.stderr
    for label in (Label.VALID, Label.REFLECTIVE_SURFACE, Label.BEHIND_REFLECTIVE):
        assert colour_pixels(png, label) > 50, label.name


def test_draws_the_echoes_of_an_input_only_bag(ros_messages, tmp_path):
    from ohm_mirror_detector3d import scanner, simulate
    sweep = simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=20), seed=1)
    path = tmp_path / 'input.bag'
    ros_messages.write_sweeps_bag(str(path), [sweep])
    png = tmp_path / 'echoes.png'
    p = run(path, '--out', png, '--dpi', 50)
    assert p.returncode == 0, p.stderr
    # plot_echoes draws echo 1 orange, echo 2 red.
    import matplotlib.image
    image = (matplotlib.image.imread(str(png))[..., :3] * 255).round()
    assert np.sum(np.all(np.abs(image - [255, 165, 0]) <= 10, axis=-1)) > 50


def test_a_bag_without_sweeps_is_refused_with_the_topics_it_has(ros_messages, tmp_path):
    import rosbag
    from std_msgs.msg import String
    path = tmp_path / 'other.bag'
    with rosbag.Bag(str(path), 'w') as bag:
        bag.write('/chatter', String(data='hi'))
    p = run(path, '--out', tmp_path / 'x.png')
    assert p.returncode != 0
    assert '/prefilter/labelled' in p.stderr and '/chatter' in p.stderr
