"""Paper-style figures are written (Agg backend)."""
import pytest

from ohm_mirror_detector3d.simulate import xyz


def test_figures_are_written(tmp_path, experiment1_sweep):
    pytest.importorskip('matplotlib')
    from ohm_mirror_detector3d import plots
    gt = experiment1_sweep.ground_truth
    path = plots.plot_views(xyz(gt), gt['label'], str(tmp_path / 'views.png'), 'exp1', experiment1_sweep.objects,
                            max_points=20000)
    assert (tmp_path / 'views.png').stat().st_size > 10000 and path.endswith('views.png')
    plots.plot_echoes(xyz(experiment1_sweep.echo1), xyz(experiment1_sweep.echo2), str(tmp_path / 'echoes.png'))
    assert (tmp_path / 'echoes.png').exists()
