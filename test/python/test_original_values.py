"""The original launch file's values through prefilter_bag on the original's kind of sweep (issue 15
item 3): a rotating Hokuyo, experiment 1's 60 x 40 cm mirror, 100, 200 and 400 scans per half
rotation, range noise sigma 1 cm (the simulator's hokuyo_utm30lx_ew preset, realistic physics), as
the original driver's CoordDistMulti. The legacy values that mean something else here are mapped
(README "Replacing the original node"); the mirror must be found, once, typed mirror, within the
issue's 2 cm of its size.
"""
import os
import xml.etree.ElementTree as ElementTree

import pytest

from test_prefilter_bag import REPO, binary, read_all, run  # noqa: F401 (binary is a fixture)

LAUNCH = os.path.join(REPO, 'test', 'legacy_launch', 'ohm_mirror_detector3D.launch')
MIRROR = 1  # ReflectiveObject.type
SIZE_TOLERANCE = 0.02  # m


def original_values():
    """The numbers the original launch file sets, as a YAML mapping."""
    node = ElementTree.parse(LAUNCH).getroot().find('node')
    lines = []
    for param in node.findall('param'):
        try:
            float(param.get('value'))
        except ValueError:
            continue  # topics and frames: not pre-filter values
        lines.append('%s: %s' % (param.get('name'), param.get('value')))
    return '\n'.join(lines) + '\n'


@pytest.mark.parametrize('scans', [100, 200, 400])
def test_the_originals_values_find_the_mirror_typed_mirror_at_its_size(binary, ros_messages, tmp_path, scans):  # noqa: F811
    from ohm_mirror_detector3d import scanner, simulate
    from ohm_mirror_detector3d.hokuyo3d_legacy import legacy_classes, legacy_messages
    sweep = simulate.simulate_sweep('experiment1', scanner.preset('hokuyo_utm30lx_ew', scans=scans), seed=1)
    truth, = sweep.objects
    params, in_bag, out_bag = tmp_path / 'original.yaml', tmp_path / 'in.bag', tmp_path / 'out.bag'
    params.write_text(original_values())
    classes = legacy_classes()
    ros_messages.write_sweeps_bag(str(in_bag), [sweep],
                                  to_messages=lambda s, t, f=None: legacy_messages(s, t, f, classes))
    p = run(binary, in_bag, out_bag, '--params', params, '--input-topic', '/coord_dist', '--only-outputs')
    assert 'outlierFilter_minNeighbors 50 within outlierFilter_searchRadius 0.1 m' in p.stderr
    assert 'max_Dist_ICP 0.01 m' in p.stderr
    objects, = [m for topic, m, _ in read_all(out_bag) if topic.endswith('/objects')]
    mirrors = [o for o in objects.objects if o.type == MIRROR]
    assert len(mirrors) == 1, [(o.type, o.width, o.height) for o in objects.objects]
    size = (mirrors[0].width, mirrors[0].height)
    assert abs(size[0] - truth['width']) <= SIZE_TOLERANCE, size
    assert abs(size[1] - truth['height']) <= SIZE_TOLERANCE, size
