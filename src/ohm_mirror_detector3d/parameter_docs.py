"""cfg/PreFilter.cfg and the README's parameter tables, made from the parameter table
(include/ohm_mirror_detector3d/core/parameters.def, as the bindings export it).

After changing the table (and building), regenerate both:

    python3 -m ohm_mirror_detector3d.parameter_docs --write

test/python/test_parameter_docs.py fails while either differs from what this makes.
"""
import argparse
import os
import sys

from .core import PARAMETER_TABLE

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
CFG = os.path.join('cfg', 'PreFilter.cfg')
README = 'README.md'
README_BEGIN = ('<!-- The parameter tables are made from include/ohm_mirror_detector3d/core/parameters.def by '
                '`python3 -m ohm_mirror_detector3d.parameter_docs --write`: edit the table, not these lines. -->')
README_END = '<!-- End of the generated parameter tables. -->'

_CFG_HEAD = '''#!/usr/bin/python3
# Parameters of the pre-filter, with the names and defaults of the original launch file.
# Made from the parameter table (include/ohm_mirror_detector3d/core/parameters.def) by
# `python3 -m ohm_mirror_detector3d.parameter_docs --write`: edit the table, not this file.
# No min/max are given on purpose: dynamic_reconfigure would silently clamp a value
# to them, and the package refuses bad values with a message instead (Params::validate).
PACKAGE = "ohm_mirror_detector3d"

from dynamic_reconfigure.parameter_generator_catkin import ParameterGenerator, double_t, int_t

gen = ParameterGenerator()
'''
_CFG_TAIL = '''
exit(gen.generate(PACKAGE, "ohm_mirror_detector3d", "PreFilter"))
'''

_README_TYPES = {'real': 'double', 'integer': 'int', 'text': 'string', 'real_list': 'double[]'}
_CFG_TYPES = {'real': 'double_t', 'integer': 'int_t'}
# Units shown beside a value; counts need none.
_SHOWN_UNITS = ('m', 'm^2', 'deg', 's')


def _number(value):
    return '%g' % value


def _row(name):
    return next(row for row in PARAMETER_TABLE if name in row['names'])


def allowed(row, ascii_only=False):
    """The allowed values of a row in words: its bounds and relations, or its `allowed` text."""
    if row['type'] not in ('real', 'integer'):
        return row['allowed']
    at_least, at_most = ('>=', '<=') if ascii_only else ('≥', '≤')
    lower, upper = row['lower'], row['upper']
    parts = []
    if lower and upper:
        parts.append('%s%s, %s%s' % ('[' if lower['inclusive'] else '(', _number(lower['value']),
                                     _number(upper['value']), ']' if upper['inclusive'] else ')'))
    elif lower:
        parts.append('%s %s' % (at_least if lower['inclusive'] else '>', _number(lower['value'])))
    elif upper:
        parts.append('%s %s' % (at_most if upper['inclusive'] else '<', _number(upper['value'])))
    if row['above']:
        parts.append('> ' + _row(row['above'])['label'])
    parts += ['< ' + other['label'] for other in PARAMETER_TABLE if other['above'] == row['name']]
    if row.get('automatic'):
        parts.append('0: automatic')
    return ', '.join(parts) or 'any number'


def _plain(text):
    return text.replace('`', '')


def cfg_description(row):
    """The row's description in cfg/PreFilter.cfg: symbol, unit, documentation, allowed range."""
    unit = '[%s]' % row['unit'] if row['unit'] in _SHOWN_UNITS else ''
    if row['symbol']:
        prefix = '%s%s: ' % (row['symbol'], ' ' + unit if unit else '')
    else:
        prefix = unit + ' ' if unit else ''
    values = allowed(row, ascii_only=True)
    # An interval brings its own brackets.
    return '%s%s %s' % (prefix, _plain(row['doc']), values if values[0] in '([' else '(%s)' % values)


def cfg_text():
    """The whole of cfg/PreFilter.cfg: one gen.add per reconfigurable row, in the table's order."""
    lines = ['gen.add(%s, %s, 0, %s, %r)' % (_quoted(row['name']), _CFG_TYPES[row['type']],
                                              _quoted(cfg_description(row)), row['default'])
             for row in PARAMETER_TABLE if row['reconfigurable']]
    return _CFG_HEAD + '\n'.join(lines) + '\n' + _CFG_TAIL


def _quoted(text):
    return '"%s"' % text.replace('\\', '\\\\').replace('"', '\\"')


def _cell(text):
    return text.replace('|', '\\|')


def _names(row):
    others = row['names'][1:]
    return '`%s`' % row['name'] + (' (%s)' % ', '.join('`%s`' % n for n in others) if others else '')


def _default(row):
    if row.get('automatic'):
        return '0: automatic, %s' % row['automatic']
    if row['type'] in ('real', 'integer'):
        return repr(row['default'])
    if row['default']:
        return '`%s`' % row['default']
    return '(%s)' % row['when_unset']


def readme_tables():
    """The README's two parameter tables (reconfigurable, then start-up only), with the markers."""
    lines = [README_BEGIN, '',
             '| name (paper symbol) | type | default | allowed | meaning |', '|---|---|---|---|---|']
    for row in PARAMETER_TABLE:
        if row['reconfigurable']:
            unit = ' [%s]' % row['unit'] if row['unit'] in _SHOWN_UNITS else ''
            lines.append('| %s | %s | %s | %s | %s |' % (_names(row), _README_TYPES[row['type']], _default(row),
                                                        _cell(allowed(row)), _cell(row['doc']) + unit))
    lines += ['', 'Start-up only (not reconfigurable):', '',
              '| name | type | default | allowed | meaning |', '|---|---|---|---|---|']
    for row in PARAMETER_TABLE:
        if not row['reconfigurable']:
            unit = ' [%s]' % row['unit'] if row['unit'] in _SHOWN_UNITS else ''
            lines.append('| %s | %s | %s | %s | %s |' % (_names(row), _README_TYPES[row['type']], _default(row),
                                                        _cell(allowed(row)) + unit, _cell(row['doc'])))
    lines += ['', README_END]
    return '\n'.join(lines) + '\n'


def readme_with_tables(readme):
    """The README text with its generated block replaced by readme_tables()."""
    begin = readme.index(README_BEGIN)
    end = readme.index(README_END) + len(README_END) + 1
    return readme[:begin] + readme_tables() + readme[end:]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--write', action='store_true', help='rewrite cfg/PreFilter.cfg and the README tables')
    parser.add_argument('--repo', default=REPO, help='the repository (default: the one of this file)')
    args = parser.parse_args(argv)
    cfg_path, readme_path = os.path.join(args.repo, CFG), os.path.join(args.repo, README)
    with open(readme_path, encoding='utf-8') as f:
        readme = f.read()
    with open(cfg_path, encoding='utf-8') as f:
        cfg = f.read()
    wanted = {cfg_path: cfg_text(), readme_path: readme_with_tables(readme)}
    current = {cfg_path: cfg, readme_path: readme}
    stale = [path for path in wanted if wanted[path] != current[path]]
    if args.write:
        for path in stale:
            with open(path, 'w', encoding='utf-8') as f:
                f.write(wanted[path])
            print('wrote', path)
        return 0
    for path in stale:
        print('%s differs from the parameter table (run with --write)' % path, file=sys.stderr)
    return 1 if stale else 0


if __name__ == '__main__':
    sys.exit(main())
