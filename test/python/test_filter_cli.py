"""python3 -m ohm_mirror_detector3d.filter on PLY, PCD and NPZ files (no ROS), and the readers and
writers of cloud_files.py. The files are simulated sweeps written in the test."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the bindings are not built')

from ohm_mirror_detector3d import cloud_files, scanner, simulate  # noqa: E402
from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays  # noqa: E402
from ohm_mirror_detector3d.filter import main  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOKUYO_PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')
DUAL_PARAMS = os.path.join(REPO, 'launch', 'dual_return_params.yaml')
ENCODINGS = [('ply', 'ascii'), ('ply', 'binary_little_endian'), ('pcd', 'ascii'), ('pcd', 'binary')]


@pytest.fixture(scope='module')
def sweep():
    return simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=80, range_noise=0.01), seed=5)


@pytest.fixture(scope='module')
def pair_cloud(sweep):
    """Both echoes in one cloud with an echo field (the nodelet's `labelled` layout), NaNs dropped:
    beams with a return only (a NaN beam is no beam to a file)."""
    keep = np.isfinite(sweep.echo1['x'])
    columns = {}
    for name in ('x', 'y', 'z', 'intensity'):
        columns[name] = np.r_[sweep.echo1[name][keep], sweep.echo2[name][keep]]
    columns['echo'] = np.repeat(np.array([1, 2], np.uint8), keep.sum())
    return cloud_files.structured(columns), keep


@pytest.fixture(scope='module')
def expected_pair(sweep, pair_cloud):
    _, keep = pair_cloud
    s = sweep
    return core.Pipeline(core.Params.from_yaml(HOKUYO_PARAMS)).filter(s.echo1[keep], s.echo2[keep])


def run_cli(*args):
    return main([str(a) for a in args] + ['--quiet'])


@pytest.mark.parametrize('fmt, encoding', ENCODINGS)
def test_pair_files_are_labelled_in_their_own_format(tmp_path, pair_cloud, expected_pair, fmt, encoding):
    cloud, _ = pair_cloud
    path = tmp_path / ('scan.' + fmt)
    cloud_files.write_new(path, cloud, encoding)
    assert run_cli(path, '--params', HOKUYO_PARAMS) == 0
    out = cloud_files.read_cloud(tmp_path / ('scan.labelled.' + fmt))
    assert out.encoding == encoding
    assert out.points.dtype.names == cloud.dtype.names + ('label',)
    for name in cloud.dtype.names:
        np.testing.assert_array_equal(out.points[name], cloud[name])
    np.testing.assert_array_equal(out.points['label'], expected_pair.labelled['label'])
    objects = json.loads((tmp_path / 'scan.objects.json').read_text())
    assert [o['type_name'] for o in objects['objects']] == ['mirror']
    assert objects['objects'][0]['width'] == pytest.approx(expected_pair.objects[0]['width'])
    assert objects['label_counts'] == expected_pair.label_counts()
    assert objects['mode'] == 'pair'


def test_pair_without_echo_field_is_halves(tmp_path, pair_cloud, expected_pair):
    cloud, _ = pair_cloud
    plain = cloud_files.structured({n: cloud[n] for n in ('x', 'y', 'z', 'intensity')})
    cloud_files.write_new(tmp_path / 'halves.ply', plain)
    assert run_cli(tmp_path / 'halves.ply', '--out', tmp_path / 'result.ply', '--params', HOKUYO_PARAMS) == 0
    out = cloud_files.read_cloud(tmp_path / 'result.ply')
    np.testing.assert_array_equal(out.points['label'], expected_pair.labelled['label'])
    assert (tmp_path / 'result.objects.json').exists()


def test_npz_pair(tmp_path, sweep, expected_pair, pair_cloud):
    _, keep = pair_cloud
    path = tmp_path / 'scan.npz'
    np.savez(path, echo1=sweep.echo1[keep], echo2=sweep.echo2[keep], stamp=np.array(12.5))
    assert run_cli(path, '--params', HOKUYO_PARAMS) == 0
    with np.load(tmp_path / 'scan.labelled.npz') as out:
        np.testing.assert_array_equal(np.r_[out['label1'], out['label2']], expected_pair.labelled['label'])
        for name in core.OUTPUT_DTYPE.names:
            np.testing.assert_array_equal(out['cleaned'][name], expected_pair.cleaned[name])
        assert float(out['stamp']) == 12.5  # the input's arrays are kept


@pytest.mark.parametrize('fmt, encoding', ENCODINGS + [('npz', None)])
def test_dual_return_files(tmp_path, fmt, encoding):
    lidar = scanner.DualReturnLidar(rings=32, azimuth_steps=512, vertical_fov_deg=(-45.0, 45.0), range_noise=0.01)
    sweep = simulate.simulate_sweep('experiment1', lidar, seed=2)
    cloud, _, _ = dual_return_arrays(sweep, first_return='mixed')
    params = tmp_path / 'params.yaml'
    params.write_text(open(DUAL_PARAMS).read().replace('0.17578125', '0.703125'))  # 512 columns
    expected = core.Pipeline(core.Params.from_yaml(str(params))).filter_dual_return(cloud)
    path = tmp_path / ('lidar.' + fmt)
    if fmt == 'npz':
        np.savez(path, points=cloud)
    else:
        cloud_files.write_new(path, cloud, encoding)
    # The ring field makes it dual_return without --mode.
    assert run_cli(path, '--params', params) == 0
    if fmt == 'npz':
        with np.load(tmp_path / 'lidar.labelled.npz') as out:
            labels = out['label']
    else:
        labels = cloud_files.read_cloud(tmp_path / ('lidar.labelled.' + fmt)).points['label']
    np.testing.assert_array_equal(labels, expected.labelled['label'])
    objects = json.loads((tmp_path / 'lidar.objects.json').read_text())
    assert objects['mode'] == 'dual_return' and objects['points'] == len(cloud)


def test_a_folder_with_progress_and_a_bad_file(tmp_path, pair_cloud, expected_pair):
    cloud, _ = pair_cloud
    folder = tmp_path / 'in'
    folder.mkdir()
    for name in ('a.ply', 'b.pcd'):
        cloud_files.write_new(folder / name, cloud)
    (folder / 'broken.pcd').write_text('VERSION 0.7\nFIELDS x y\n')
    (folder / 'notes.txt').write_text('not a cloud')
    p = subprocess.run([sys.executable, '-m', 'ohm_mirror_detector3d.filter', str(folder), '--out',
                        str(tmp_path / 'out'), '--params', HOKUYO_PARAMS],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, timeout=300)
    assert p.returncode == 1, p.stderr  # one file failed, the others were done
    assert '[1/3] %s: pair' % (folder / 'a.ply') in p.stderr and '1 mirror' in p.stderr
    assert '[2/3] %s: pair' % (folder / 'b.pcd') in p.stderr
    assert '[3/3] %s: error:' % (folder / 'broken.pcd') in p.stderr
    assert sorted(os.listdir(tmp_path / 'out')) == ['a.labelled.ply', 'a.objects.json', 'b.labelled.pcd',
                                                     'b.objects.json']
    # A glob; earlier outputs (*.labelled.*) are not taken as inputs again.
    cloud_files.write_new(folder / 'a.labelled.ply', cloud)
    assert run_cli(str(folder / '*.ply'), '--out', tmp_path / 'glob') == 0
    assert sorted(os.listdir(tmp_path / 'glob')) == ['a.labelled.ply', 'a.objects.json']


def test_usage_errors(tmp_path, pair_cloud):
    cloud, _ = pair_cloud
    cloud_files.write_new(tmp_path / 'a.ply', cloud)
    assert run_cli(tmp_path / 'missing.ply') == 2
    bad = tmp_path / 'bad.yaml'
    bad.write_text('outlierFilter_searchRadius: -1\n')
    assert run_cli(tmp_path / 'a.ply', '--params', bad) == 2
    bad.write_text('input_mode: multi_echo_scan\n')
    assert run_cli(tmp_path / 'a.ply', '--params', bad) == 2
    odd = cloud_files.structured({n: cloud[n][:5] for n in ('x', 'y', 'z')})
    cloud_files.write_new(tmp_path / 'odd.pcd', odd)
    assert run_cli(tmp_path / 'odd.pcd') == 1  # pair mode needs an even count without an echo field
    assert run_cli(tmp_path / 'a.ply', '--mode', 'dual_return') == 1  # no ring field


# --- readers and writers on files as other tools write them -----------------------------------------

def test_ply_with_faces_and_comments_is_written_back_with_them(tmp_path):
    text = ('ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\nproperty float x\nproperty float y\n'
            'property float z\nproperty uchar echo\nelement face 1\nproperty list uchar int vertex_indices\n'
            'end_header\n0 0 1 1\n0 1 1 1\n0 0 1.5 2\n0 1 1.5 2\n3 0 1 2\n')
    (tmp_path / 'mesh.ply').write_text(text)
    cloud = cloud_files.read_cloud(tmp_path / 'mesh.ply')
    np.testing.assert_array_equal(cloud.points['z'], np.float32([1, 1, 1.5, 1.5]))
    cloud_files.write_cloud(tmp_path / 'out.ply', cloud, cloud_files.append_field(cloud.points, 'label',
                                                                                  np.arange(4, dtype=np.uint8)))
    out = (tmp_path / 'out.ply').read_text()
    assert 'comment made by hand' in out and out.endswith('3 0 1 2\n')
    assert 'property uchar label\nelement face 1\nproperty list uchar int vertex_indices\nend_header' in out
    np.testing.assert_array_equal(cloud_files.read_cloud(tmp_path / 'out.ply').points['label'], np.arange(4))


def test_big_endian_ply_and_pcl_padding_fields(tmp_path):
    points = np.array([(1.0, 2.0, 3.0), (4.0, 5.0, 6.0)], [('x', '>f4'), ('y', '>f4'), ('z', '>f4')])
    (tmp_path / 'be.ply').write_bytes(b'ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\n'
                                      b'property float y\nproperty float z\nend_header\n' + points.tobytes())
    np.testing.assert_array_equal(cloud_files.read_cloud(tmp_path / 'be.ply').points['y'], [2.0, 5.0])
    # PCL's binary layout: x y z, 4 padding bytes ('_'), intensity, 12 padding bytes ('_').
    dtype = np.dtype([('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('_1', 'u1', (4,)), ('intensity', '<f4'),
                      ('_2', 'u1', (12,))])
    data = np.zeros(2, dtype)
    data['x'], data['intensity'] = [1, 2], [10, 20]
    (tmp_path / 'pcl.pcd').write_bytes(b'VERSION 0.7\nFIELDS x y z _ intensity _\nSIZE 4 4 4 1 4 1\n'
                                       b'TYPE F F F U F U\nCOUNT 1 1 1 4 1 12\nWIDTH 2\nHEIGHT 1\n'
                                       b'VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n' + data.tobytes())
    cloud = cloud_files.read_cloud(tmp_path / 'pcl.pcd')
    np.testing.assert_array_equal(cloud.points['intensity'], [10, 20])
    cloud_files.write_cloud(tmp_path / 'out.pcd', cloud, cloud_files.append_field(cloud.points, 'label',
                                                                                  np.uint8([4, 5])))
    head = (tmp_path / 'out.pcd').read_bytes().split(b'DATA binary\n')[0].decode()
    assert 'FIELDS x y z _ intensity _ label' in head and 'COUNT 1 1 1 4 1 12 1' in head
    again = cloud_files.read_cloud(tmp_path / 'out.pcd')
    np.testing.assert_array_equal(again.points['label'], [4, 5])
    np.testing.assert_array_equal(again.points['intensity'], [10, 20])
    (tmp_path / 'c.pcd').write_bytes(b'FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n'
                                     b'POINTS 1\nDATA binary_compressed\n')
    with pytest.raises(ValueError, match='binary_compressed is not supported'):
        cloud_files.read_cloud(tmp_path / 'c.pcd')
