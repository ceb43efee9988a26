"""Nothing is lost: over every simulator scene and every input mode, the `labelled` output holds
exactly one point per input point of both echoes (what the filter drops from `cleaned` is still
in `labelled`, as nanPoint or error). Runs prefilter_bag (the nodelet's own MessagePipeline and
input adapters, no master) on one bag per mode holding a small sweep of every scene.
"""
import os

import numpy as np
import pytest

from test_prefilter_bag import REPO, binary, read_all, run  # noqa: F401 (fixture)

SCANS = 24  # rotating Hokuyo: 24 scans x 1080 beams per sweep, small but covering the whole room
PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')


def scene_names():
    from ohm_mirror_detector3d import scene
    return scene.names()


def labelled_counts(out_bag):
    """{stamp: number of labelled points} and the labels seen, from an output bag."""
    counts, labels = {}, set()
    for _, msg, _ in read_all(out_bag, ['/prefilter/labelled']):
        counts[msg.header.stamp] = msg.width * msg.height
        data = np.frombuffer(msg.data, np.uint8).reshape(-1, msg.point_step)
        labels.update(np.unique(data[:, 16]).tolist())
    return counts, labels


def assert_every_sweep_whole(binary, in_bag, out_bag, expected, *args):  # noqa: F811
    p = run(binary, in_bag, out_bag, *args)
    assert 'sweeps dropped:   0' in p.stderr, p.stderr
    counts, labels = labelled_counts(out_bag)
    assert counts == expected
    assert labels <= set(range(1, 10)), 'unknown or unchecked labels: %s' % labels


@pytest.fixture(scope='module')
def hokuyo_sweeps(ros_messages):
    from ohm_mirror_detector3d import scanner, simulate
    return [simulate.simulate_sweep(name, scanner.RotatingHokuyo(scans=SCANS), seed=k)
            for k, name in enumerate(scene_names())]


@pytest.fixture(scope='module')
def pair_bag(hokuyo_sweeps, ros_messages, tmp_path_factory):
    path = tmp_path_factory.mktemp('nothing_lost') / 'pair.bag'
    stamps = ros_messages.write_sweeps_bag(str(path), hokuyo_sweeps)
    expected = {stamp: 2 * sweep.num_beams for stamp, sweep in zip(stamps, hokuyo_sweeps)}
    return path, expected


@pytest.mark.parametrize('mode', ['pair', 'two_topics'])
def test_echo_clouds_every_scene(binary, pair_bag, tmp_path, mode):  # noqa: F811
    in_bag, expected = pair_bag
    assert len(expected) == len(scene_names())
    assert_every_sweep_whole(binary, in_bag, tmp_path / 'out.bag', expected, '--params', PARAMS,
                             '--input-mode', mode)


def test_hokuyo3d_legacy_every_scene(binary, hokuyo_sweeps, ros_messages, tmp_path):  # noqa: F811
    from ohm_mirror_detector3d.hokuyo3d_legacy import legacy_classes, legacy_messages
    classes = legacy_classes()
    in_bag = tmp_path / 'in.bag'
    stamps = ros_messages.write_sweeps_bag(str(in_bag), hokuyo_sweeps, to_messages=lambda s, t, f=None: (
        legacy_messages(s, t, f, classes)))
    expected = {stamp: 2 * sweep.num_beams for stamp, sweep in zip(stamps, hokuyo_sweeps)}
    assert_every_sweep_whole(binary, in_bag, tmp_path / 'out.bag', expected, '--params', PARAMS,
                             '--input-mode', 'hokuyo3d_legacy')


def test_dual_return_every_scene(binary, ros_messages, tmp_path):  # noqa: F811
    from ohm_mirror_detector3d import scanner, simulate
    from ohm_mirror_detector3d.dual_return_cloud import dual_return_messages
    lidar = scanner.DualReturnLidar(rings=16, azimuth_steps=1024, vertical_fov_deg=(-45.0, 45.0))
    sweeps = [simulate.simulate_sweep(name, lidar, seed=k) for k, name in enumerate(scene_names())]
    in_bag = tmp_path / 'in.bag'
    # keep_empty: beams without a return are in the cloud too (as NaN), and must be in labelled.
    stamps = ros_messages.write_sweeps_bag(str(in_bag), sweeps, to_messages=lambda s, t, f=None: (
        dual_return_messages(s, t, f, keep_empty=True)))
    clouds = {msg.header.stamp: msg.width * msg.height for _, msg, _ in read_all(in_bag, ['/points'])}
    assert sorted(clouds) == sorted(stamps)
    assert_every_sweep_whole(binary, in_bag, tmp_path / 'out.bag', clouds, '--params',
                             os.path.join(REPO, 'launch', 'dual_return_params.yaml'), '--input-mode', 'dual_return')


def test_multi_echo_scan_every_scene(binary, ros_messages, tmp_path):  # noqa: F811
    """Scans + tf of a rotating Hokuyo: every sweep holds both echoes of every beam of every scan
    up to its stamp (the scan that completes the last sweep starts the next one, not output)."""
    from ohm_mirror_detector3d import scanner
    from ohm_mirror_detector3d.scan_sequence import ScanStream
    params = tmp_path / 'params.yaml'
    with open(PARAMS) as f:
        params.write_text(f.read().replace('input_mode: pair', 'input_mode: multi_echo_scan') +
                          '\nsweep_frame: base_link\nrotation_axis: [0, 0, 1]\n')
    for k, name in enumerate(scene_names()):
        in_bag, out_bag = tmp_path / ('%s.bag' % name), tmp_path / ('%s_out.bag' % name)
        stream = ScanStream(name, scanner.RotatingHokuyo(scans=SCANS, continuous=True), seed=k)
        ros_messages.write_scan_stream_bag(str(in_bag), stream, 1)
        scans = [msg for _, msg, _ in read_all(in_bag, ['/scan_echoes'])]
        p = run(binary, in_bag, out_bag, '--params', params)
        assert 'sweeps processed: 1' in p.stderr and 'sweeps dropped:   0' in p.stderr, (name, p.stderr)
        counts, labels = labelled_counts(out_bag)
        (stamp, points), = counts.items()
        covered = [s for s in scans if s.header.stamp <= stamp]
        assert points == sum(2 * len(s.ranges) for s in covered), name
        assert len(covered) == len(scans) - 1, name
        assert labels <= set(range(1, 10)), name
