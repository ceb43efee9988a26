"""Evaluation reports: JSON and a Markdown summary of metrics results (numpy only)."""
import json
import os

import numpy as np

from .metrics import strip_raw

_TYPE_NAMES = {0: 'unknown', 1: 'mirror', 2: 'glass'}


def jsonable(x):
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items() if not str(k).startswith('_')}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (np.floating, float)):
        return None if not np.isfinite(x) else float(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def _fmt(v, digits=4):
    if v is None:
        return '-'
    if isinstance(v, float):
        return ('%.' + str(digits) + 'g') % v
    return str(v)


def _cm(v):
    return '-' if v is None else '%.1f' % (100 * v)


def to_markdown(summary, title='Evaluation'):
    """Markdown tables of an aggregated (or single-sweep) result."""
    lines = ['# %s' % title, '']
    if 'sweeps' in summary:
        lines += ['Sweeps evaluated: %d' % summary['sweeps'], '']
    lines += ['## Points', '', '| metric | value |', '|---|---|']
    c = summary.get('counts', {})
    rows = [
        ('physical returns', summary.get('physical_returns')),
        ('phantoms (ground truth)', c.get('phantoms')),
        ('phantoms left in cleaned at a wrong place (> 5 cm)', c.get('phantoms_wrong_place')),
        ('fraction of phantoms left at a wrong place', summary.get('phantom_wrong_place_fraction')),
        ('fraction of cleaned points that are misplaced phantoms', summary.get('cleaned_wrong_place_fraction')),
        ('phantoms dropped', c.get('phantoms_dropped')),
        ('phantoms back-projected (within 5 cm)', '%s (%s)' % (c.get('phantoms_back_projected', '-'),
                                                                 c.get('phantoms_back_projected_correctly', '-'))),
        ('real points (ground truth)', c.get('real')),
        ('real points lost from cleaned', c.get('real_lost')),
        ('fraction of real points lost', summary.get('real_lost_fraction')),
        ('fraction of real points displaced (> 5 cm)', summary.get('real_displaced_fraction')),
    ]
    bp = summary.get('backprojection_error') or {}
    rows += [('back-projection error median [cm]', _cm(bp.get('median'))),
             ('back-projection error 95th percentile [cm]', _cm(bp.get('p95')))]
    lines += ['| %s | %s |' % (k, _fmt(v)) for k, v in rows]
    for key, name in (('confusion_coarse', 'Confusion (coarse classes)'), ('confusion', 'Confusion (labels)')):
        if key not in summary:
            continue
        cm = summary[key]
        m = np.asarray(cm['matrix'])
        keep_rows = [i for i in range(len(cm['rows'])) if m[i].sum() > 0]
        keep_cols = [j for j in range(len(cm['cols'])) if m[:, j].sum() > 0]
        lines += ['', '## %s' % name, '', 'Rows: ground truth; columns: filter.', '',
                  '| truth \\ filter | ' + ' | '.join(cm['cols'][j] for j in keep_cols) + ' | recall |',
                  '|---|' + '---|' * (len(keep_cols) + 1)]
        for i in keep_rows:
            diag = m[i, i] if i < m.shape[1] else 0
            lines.append('| %s | ' % cm['rows'][i] + ' | '.join(str(m[i, j]) for j in keep_cols)
                         + ' | %s |' % _fmt(diag / m[i].sum()))
    if summary.get('objects'):
        lines += ['', '## Objects', '',
                  '| object | type | true w x h [cm] | detected | det. type | det. w x h [cm] | w/h error [cm] '
                  '| sorted sides error [cm] | corner error mean/max [cm] |',
                  '|---|---|---|---|---|---|---|---|---|']
        for o in summary['objects']:
            pre = 'mean_' if 'detection_rate' in o else ''
            det = ('%.0f%%' % (100 * o['detection_rate'])) if 'detection_rate' in o else ('yes' if o['matched'] else 'no')
            if 'detection_rate' in o:
                dtype = '%s correct' % _fmt(o.get('type_correct_rate'), 3)
            else:
                dtype = _TYPE_NAMES.get(o.get('detected_type'), '-') if o['matched'] else '-'
            ss = o.get(pre + 'sorted_sides_error')
            lines.append('| %s | %s | %s x %s | %s | %s | %s x %s | %s / %s | %s | %s / %s |' % (
                o.get('truth_name') or o['truth_id'], _TYPE_NAMES.get(o['truth_type'], '?'),
                _cm(o['truth_width']), _cm(o['truth_height']), det, dtype,
                _cm(o.get(pre + 'detected_width')), _cm(o.get(pre + 'detected_height')),
                _cm(o.get(pre + 'width_error')), _cm(o.get(pre + 'height_error')),
                ('%s / %s' % (_cm(ss[0]), _cm(ss[1]))) if ss else '-',
                _cm(o.get(pre + 'corner_error_mean')), _cm(o.get(pre + 'corner_error_max'))))
    return '\n'.join(lines) + '\n'


def write_report(out_dir, summary, per_sweep=(), title='Evaluation'):
    """Writes DIR/evaluation.json (summary + per-sweep results) and DIR/evaluation.md. Returns the paths."""
    os.makedirs(out_dir, exist_ok=True)
    json_path = os.path.join(out_dir, 'evaluation.json')
    md_path = os.path.join(out_dir, 'evaluation.md')
    with open(json_path, 'w') as f:
        json.dump(jsonable({'summary': summary, 'sweeps': [strip_raw(r) for r in per_sweep]}), f, indent=1)
    with open(md_path, 'w') as f:
        f.write(to_markdown(jsonable(summary), title))
    return json_path, md_path
