"""`pip install` of the repository into a fresh virtual environment of Debian's /usr/bin/python3,
as on a machine without ROS: no system site packages (so no rospy), no catkin workspace in the
environment, the machine's own pip configuration. pip builds the core and its bindings with the
backend of pyproject.toml (pip/CMakeLists.txt); then, in that environment, the package imports
without rospy, labels a simulated sweep exactly as the catkin-built module of this process does,
and the file CLI (console script ohm-mirror-filter and python -m ohm_mirror_detector3d.filter)
writes the same labelled PLY as the catkin one.

Run by ctest after `source devel/setup.bash` (the catkin module is the reference). The build takes
about a minute and a half on 2 cores (precompiled headers, as the catkin build); it runs under
`nice` and leaves nothing in the repository (pip builds in a temporary folder)."""
import json
import os
import subprocess
import textwrap

import numpy as np
import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core', reason='the catkin-built bindings are not built')

from ohm_mirror_detector3d import cloud_files, filter as catkin_filter, scanner, simulate  # noqa: E402

# The repository itself, not the catkin workspace's folder of links to it.
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
HOKUYO_PARAMS = os.path.join(REPO, 'launch', 'rotating_hokuyo_params.yaml')
SYSTEM_PYTHON = '/usr/bin/python3'
PIP_SECONDS = 900  # a hung build fails the test instead of blocking ctest
# What a machine without ROS has in its environment: the pip configuration (PIP_* variables and
# the configuration files found through HOME and XDG_*), proxies and certificates, the locale. Not
# the catkin workspace's PYTHONPATH, LD_LIBRARY_PATH, CMAKE_PREFIX_PATH or ROS_* variables.
KEPT_VARIABLES = ('HOME', 'TMPDIR', 'LANG', 'LC_ALL', 'XDG_CONFIG_HOME', 'XDG_CONFIG_DIRS', 'XDG_CACHE_HOME',
                  'SSL_CERT_FILE', 'SSL_CERT_DIR', 'REQUESTS_CA_BUNDLE')


def rosless_environment():
    env = {k: v for k, v in os.environ.items()
           if k in KEPT_VARIABLES or k.startswith('PIP_') or k.lower().endswith('_proxy')}
    env['PATH'] = '/usr/bin:/bin'
    # The machine's two cores, whichever generator scikit-build-core picks.
    env['CMAKE_BUILD_PARALLEL_LEVEL'] = '2'
    return env


def run(args, cwd, **kwargs):
    """args in the environment above, in cwd (a folder outside the repository: `python -c` and
    `-m` look for modules in the working folder first)."""
    return subprocess.run([str(a) for a in args], cwd=str(cwd), env=rosless_environment(), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True, **kwargs)


@pytest.fixture(scope='module')
def venv(tmp_path_factory):
    root = tmp_path_factory.mktemp('pip_install') / 'venv'
    created = run([SYSTEM_PYTHON, '-m', 'venv', root], root.parent)
    assert created.returncode == 0, 'python3 -m venv failed (Debian package python3-venv?):\n' + created.stdout
    installed = run(['nice', '-n', '10', root / 'bin' / 'python', '-m', 'pip', 'install', '--no-input', REPO],
                    root.parent, timeout=PIP_SECONDS)
    assert installed.returncode == 0, 'pip install %s failed:\n%s' % (REPO, installed.stdout[-20000:])
    return root


def venv_python(venv, script, *args):
    result = run([venv / 'bin' / 'python', '-c', textwrap.dedent(script)] + list(args), venv.parent)
    assert result.returncode == 0, result.stdout
    return result.stdout


def test_package_imports_in_the_venv_without_ros(venv):
    report = json.loads(venv_python(venv, """
        import importlib.util, json, sys
        import ohm_mirror_detector3d, ohm_mirror_detector3d.core, ohm_mirror_detector3d.filter
        print(json.dumps({
            'package': ohm_mirror_detector3d.__file__,
            'bindings': ohm_mirror_detector3d.core._core.__file__,
            'rospy_found': importlib.util.find_spec('rospy') is not None,
            'ros_modules': sorted(m for m in sys.modules if m.split('.')[0] in
                                  ('rospy', 'roslib', 'genpy', 'rosbag', 'catkin', 'catkin_pkg')),
        }))
        """))
    site_packages = str(venv / 'lib')
    assert report['package'].startswith(site_packages)
    assert report['bindings'].startswith(site_packages)
    assert not report['rospy_found']
    assert report['ros_modules'] == []
    # This process's module is the catkin one, the reference of the tests below.
    assert not core._core.__file__.startswith(str(venv))


@pytest.fixture(scope='module')
def sweep():
    return simulate.simulate_sweep('experiment1', scanner.RotatingHokuyo(scans=80, range_noise=0.01), seed=5)


def test_pip_module_labels_a_sweep_as_the_catkin_module(venv, sweep, tmp_path):
    expected = core.Pipeline(core.Params.from_yaml(HOKUYO_PARAMS)).filter(sweep.echo1, sweep.echo2)
    assert [o['type_name'] for o in expected.objects] == ['mirror']
    np.savez(tmp_path / 'sweep.npz', echo1=sweep.echo1, echo2=sweep.echo2)
    # labelled and cleaned as raw bytes (np.load does not keep a record's padding bytes).
    venv_python(venv, """
        import sys
        import numpy as np
        from ohm_mirror_detector3d import core
        sweep_file, params, out = sys.argv[1:]
        sweep = np.load(sweep_file)
        result = core.Pipeline(core.Params.from_yaml(params)).filter(sweep['echo1'], sweep['echo2'])
        open(out + '.labelled', 'wb').write(result.labelled.tobytes())
        open(out + '.cleaned', 'wb').write(result.cleaned.tobytes())
        np.savez(out + '.npz', corners=np.array([o['corners'] for o in result.objects]),
                 types=np.array([o['type'] for o in result.objects]))
        """, tmp_path / 'sweep.npz', HOKUYO_PARAMS, tmp_path / 'result')
    assert (tmp_path / 'result.labelled').read_bytes() == expected.labelled.tobytes()
    assert (tmp_path / 'result.cleaned').read_bytes() == expected.cleaned.tobytes()
    objects = np.load(tmp_path / 'result.npz')
    np.testing.assert_array_equal(objects['types'], [o['type'] for o in expected.objects])
    np.testing.assert_array_equal(objects['corners'], [o['corners'] for o in expected.objects])


@pytest.fixture(scope='module')
def ply_file(sweep, tmp_path_factory):
    """Both echoes of the sweep's beams with a return in one binary PLY with an echo field."""
    keep = np.isfinite(sweep.echo1['x'])
    columns = {name: np.r_[sweep.echo1[name][keep], sweep.echo2[name][keep]] for name in ('x', 'y', 'z', 'intensity')}
    columns['echo'] = np.repeat(np.array([1, 2], np.uint8), keep.sum())
    path = tmp_path_factory.mktemp('ply') / 'scan.ply'
    cloud_files.write_new(path, cloud_files.structured(columns), 'binary_little_endian')
    return path


def objects_of(json_path):
    """The objects file without what differs from run to run (the core's wall time)."""
    with open(str(json_path)) as f:
        data = json.load(f)
    del data['stats']
    return data


def test_console_script_and_module_write_the_catkin_cli_output(venv, ply_file, tmp_path):
    assert catkin_filter.main([str(ply_file), '--out', str(tmp_path / 'catkin.ply'), '--params', HOKUYO_PARAMS,
                               '--quiet']) == 0
    expected_cloud = (tmp_path / 'catkin.ply').read_bytes()
    expected_objects = objects_of(tmp_path / 'catkin.objects.json')
    assert [o['type_name'] for o in expected_objects['objects']] == ['mirror']

    runs = {'script': [venv / 'bin' / 'ohm-mirror-filter'],
            'module': [venv / 'bin' / 'python', '-m', 'ohm_mirror_detector3d.filter']}
    for name, command in runs.items():
        result = run(command + [ply_file, '--out', tmp_path / (name + '.ply'), '--params', HOKUYO_PARAMS], tmp_path)
        assert result.returncode == 0, result.stdout
        assert 'mirror' in result.stdout  # the progress line names what it found
        assert (tmp_path / (name + '.ply')).read_bytes() == expected_cloud, name
        assert objects_of(tmp_path / (name + '.objects.json')) == expected_objects, name


def test_console_script_help(venv):
    result = run([venv / 'bin' / 'ohm-mirror-filter', '--help'], venv.parent)
    assert result.returncode == 0, result.stdout
    assert result.stdout.startswith('usage: ohm-mirror-filter ')
    assert '--params' in result.stdout

