"""cfg/PreFilter.cfg, the README's parameter tables and the Python Params dataclass agree with the
parameter table (include/ohm_mirror_detector3d/core/parameters.def, as the bindings export it).
The generated C++ config is checked against it by the gtest test_parameters."""
import dataclasses
import os

import pytest

core = pytest.importorskip('ohm_mirror_detector3d.core',
                           reason='the bindings are not built (build, then source .ws/devel/setup.bash)')
from ohm_mirror_detector3d import parameter_docs  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIX = 'regenerate with: python3 -m ohm_mirror_detector3d.parameter_docs --write'


def read(*path):
    with open(os.path.join(REPO, *path), encoding='utf-8') as f:
        return f.read()


def test_the_reconfigure_cfg_is_made_from_the_table():
    assert read('cfg', 'PreFilter.cfg') == parameter_docs.cfg_text(), FIX


def test_the_readme_tables_are_made_from_the_table():
    readme = read('README.md')
    assert parameter_docs.readme_tables() in readme, FIX
    assert readme.count(parameter_docs.README_BEGIN) == 1


def test_every_row_is_in_the_readme_and_every_reconfigurable_row_in_the_cfg():
    readme, cfg = read('README.md'), read('cfg', 'PreFilter.cfg')
    for row in core.PARAMETER_TABLE:
        assert '| `%s`' % row['name'] in readme, row['name']
        assert ('gen.add("%s",' % row['name'] in cfg) == row['reconfigurable'], row['name']


def test_the_dataclass_holds_the_pipeline_and_core_input_rows_with_their_defaults_and_types():
    rows = [row for row in core.PARAMETER_TABLE if row['scope'] in ('pipeline', 'core_input')]
    fields = dataclasses.fields(core.Params)
    assert [f.name for f in fields] == [row['name'] for row in rows]
    for f, row in zip(fields, rows):
        assert f.default == row['default'] and type(f.default) is f.type, row['name']
        assert f.type is {'real': float, 'integer': int}[row['type']]
    # The core's own defaults, field by field.
    cpp = core.Params().to_core()
    for name, _, field, _ in core.PARAMETERS:
        assert getattr(cpp, field) == getattr(core.Params(), name)


def test_every_name_of_every_row_is_accepted_and_nothing_else():
    for row in core.PARAMETER_TABLE:
        for name in row['names']:
            value = row['default'] if row['type'] in ('real', 'integer') else 'x'
            params = core.Params.from_dict({name: value})
            if row['scope'] in ('pipeline', 'core_input'):
                assert getattr(params, row['name']) == value, name
            else:
                assert name in core.ROS_ONLY_KEYS, name
    with pytest.raises(ValueError, match='unknown parameter in parameters: queue_size'):
        core.Params.from_dict({'queue_size': 1})


def test_a_core_input_is_validated_by_its_core_check():
    row = next(r for r in core.PARAMETER_TABLE if r['name'] == 'azimuth_resolution_deg')
    assert core.Params(azimuth_resolution_deg=row['upper']['value']).validate() == []
    problems = core.Params(azimuth_resolution_deg=row['upper']['value'] * 2).validate()
    assert len(problems) == 1 and problems[0].startswith('azimuth_resolution_deg = 20 is out of range')


def test_the_check_mode_reports_stale_files(tmp_path):
    os.makedirs(str(tmp_path / 'cfg'))
    (tmp_path / 'cfg' / 'PreFilter.cfg').write_text(parameter_docs.cfg_text(), encoding='utf-8')
    readme = 'intro\n' + parameter_docs.readme_tables() + 'rest\n'
    (tmp_path / 'README.md').write_text(readme, encoding='utf-8')
    assert parameter_docs.main(['--repo', str(tmp_path)]) == 0
    (tmp_path / 'README.md').write_text(readme.replace('| `input_mode` |', '| `input_mode_typo` |'), encoding='utf-8')
    assert parameter_docs.main(['--repo', str(tmp_path)]) == 1
    assert parameter_docs.main(['--repo', str(tmp_path), '--write']) == 0
    assert (tmp_path / 'README.md').read_text(encoding='utf-8') == readme
