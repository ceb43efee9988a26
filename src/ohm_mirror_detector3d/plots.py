"""Figures in the style of the paper's (Koch et al. 2017, figs. 5-13): points coloured by label,
valid green, surface turquoise, behind orange (labels.LABEL_COLOURS); top and side views, and a
close-up of the non-valid points in the frame of the first object (its plane seen edge-on, which shows
the mirror's "thickness" of fig. 6). Uses matplotlib's Agg backend only; matplotlib is imported on use.
"""
import numpy as np

from .labels import LABEL_COLOURS, Label

_DRAW_ORDER = [Label.VALID, Label.UNCHECKED, Label.NAN_POINT, Label.ERROR, Label.BEHIND_TRANSPARENT,
               Label.BEHIND_ERROR_S, Label.BEHIND_REFLECTIVE, Label.TRANSPARENT_SURFACE, Label.ERROR_SURFACE,
               Label.REFLECTIVE_SURFACE]


def _pyplot():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def _save(plt, fig, path, title):
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _scatter(ax, u, v, labels, max_points, rng):
    for lab in _DRAW_ORDER:
        m = np.flatnonzero(labels == lab)
        if m.size == 0:
            continue
        if m.size > max_points:
            m = rng.choice(m, max_points, replace=False)
        size = 0.3 if lab == Label.VALID else 1.5
        ax.scatter(u[m], v[m], s=size, c=[LABEL_COLOURS[lab]], marker='.', linewidths=0,
                   label='%s (%d)' % (lab.name.lower(), int((labels == lab).sum())))


def _outline(ax, obj, i, j, style, colour):
    c = np.asarray(obj['corners'], float).reshape(4, 3)
    c = np.vstack([c, c[:1]])
    ax.plot(c[:, i], c[:, j], style, color=colour, linewidth=1.0)


def _object_frame(obj):
    c = np.asarray(obj['corners'], float).reshape(4, 3)
    centre = c.mean(axis=0)
    n = np.asarray(obj['plane'], float)[:3]
    n = n / np.linalg.norm(n)
    up = np.array([0.0, 0.0, 1.0]) - n * n[2]
    up = up / np.linalg.norm(up) if np.linalg.norm(up) > 1e-6 else np.cross(n, [1.0, 0.0, 0.0])
    return centre, n, up


def _draw_views(axes, xyz, labels, ground_truth_objects, detected_objects, max_points, rng, legend=True):
    """Top view, side view and (with a third axis) the object close-up of one cloud on `axes`."""
    xyz = np.asarray(xyz, float)
    labels = np.asarray(labels).astype(np.int64)
    finite = np.isfinite(xyz).all(axis=1)
    xyz, labels = xyz[finite], labels[finite]
    objects = list(ground_truth_objects) or list(detected_objects)
    for ax, (i, j, name) in zip(axes, ((0, 1, 'top view (x-y)'), (0, 2, 'side view (x-z)'))):
        _scatter(ax, xyz[:, i], xyz[:, j], labels, max_points, rng)
        for o in ground_truth_objects:
            _outline(ax, o, i, j, '--', 'blue')
        for o in detected_objects:
            _outline(ax, o, i, j, '-', 'red')
        ax.set_aspect('equal', adjustable='datalim')
        ax.set_title(name)
        ax.set_xlabel('xyz'[i] + ' [m]')
        ax.set_ylabel('xyz'[j] + ' [m]')
    if legend:
        axes[0].legend(loc='upper right', fontsize=7, markerscale=8)
    if objects and len(axes) > 2:
        ax = axes[2]
        centre, n, up = _object_frame(objects[0])
        rel = xyz - centre
        depth, height = -(rel @ n), rel @ up   # depth > 0 behind the plane (away from the sensor)
        near = (np.abs(height) < 2.0) & (depth > -1.0) & (depth < 6.0) & (labels != Label.VALID)
        _scatter(ax, depth[near], height[near], labels[near], max_points, rng)
        ax.axvline(0.0, color='blue', linestyle='--', linewidth=0.8)
        far = float(depth[near].max()) if near.any() else 0.0
        ax.set_xlim(-0.5, max(1.0, far + 0.2))   # a fixed scale, also when nothing lies behind the plane
        ax.set_title('non-valid points, plane of object %s edge-on' % objects[0].get('name', objects[0].get('id', 0)))
        ax.set_xlabel('depth behind the plane [m]')
        ax.set_ylabel('height along the plane [m]')


def plot_views(xyz, labels, path, title='', ground_truth_objects=(), detected_objects=(), max_points=150000,
               seed=0):
    """Writes a PNG with a top view (x-y), a side view (x-z) and, when objects are given, a close-up of the
    non-valid points in the frame of the first object (depth behind its plane vs. height)."""
    plt = _pyplot()
    panels = 3 if (list(ground_truth_objects) or list(detected_objects)) else 2
    fig, axes = plt.subplots(1, panels, figsize=(6 * panels, 6))
    _draw_views(axes, xyz, labels, ground_truth_objects, detected_objects, max_points, np.random.default_rng(seed))
    return _save(plt, fig, path, title)


def plot_before_after(before, after, path, title='', detected_objects=(), max_points=150000, seed=0, dpi=110,
                      panel_size=6.0):
    """The paper's before/after figure: one row per cloud, each (xyz, labels) -- `before` the labelled
    cloud as measured, `after` the cleaned one (phantoms back-projected) -- with top view, side view and,
    when objects are given, the close-up of the first object's plane."""
    plt = _pyplot()
    panels = 3 if list(detected_objects) else 2
    fig, axes = plt.subplots(2, panels, figsize=(panel_size * panels, 2 * panel_size), squeeze=False)
    rng = np.random.default_rng(seed)
    for row, ((xyz, labels), name) in enumerate(((before, 'before'), (after, 'after'))):
        _draw_views(axes[row], xyz, labels, (), detected_objects, max_points, rng)
        axes[row][0].set_title('%s filtering: %s' % (name, axes[row][0].get_title()))
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def plot_echoes(echo1_xyz, echo2_xyz, path, title=''):
    """The raw sweep like the paper's fig. 4: echo 1 orange, echo 2 red (top and side view)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    for ax, (i, j) in zip(axes, ((0, 1), (0, 2))):
        for pts, colour, name in ((echo2_xyz, 'red', 'echo 2'), (echo1_xyz, 'orange', 'echo 1')):
            p = np.asarray(pts, float)
            p = p[np.isfinite(p).all(axis=1)]
            ax.scatter(p[:, i], p[:, j], s=0.3, c=colour, marker='.', linewidths=0, label=name)
        ax.set_aspect('equal', adjustable='datalim')
        ax.set_xlabel('xyz'[i] + ' [m]')
        ax.set_ylabel('xyz'[j] + ' [m]')
    axes[0].legend(markerscale=10)
    return _save(plt, fig, path, title)
