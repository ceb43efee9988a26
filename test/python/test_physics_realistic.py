"""The realistic physics (the default): glass that reflects more towards grazing incidence, mirrors with a
sharp specular peak, partly specular metal, mixed pixels and double echoes at depth edges of plain
geometry, the second return stored only where it differs, and the four sensor presets of SENSORS.md."""
import math

import numpy as np
import pytest

from ohm_mirror_detector3d import scene as sc
from ohm_mirror_detector3d import scanner
from ohm_mirror_detector3d.dual_return_cloud import dual_return_arrays
from ohm_mirror_detector3d.labels import Label
from ohm_mirror_detector3d.physics import PhysicsParams, SceneArrays, pane_reflectance, trace
from ohm_mirror_detector3d.scanner import BeamList, DualReturnLidar
from ohm_mirror_detector3d.simulate import reported_echoes, simulate_sweep, true_xyz, xyz

GAIN = PhysicsParams().intensity_gain


def wall_x(x, material=sc.WALL, size=40.0, name='wall'):
    return sc.Rectangle((x, 0.0, 0.0), (0, 1, 0), (0, 0, 1), size, size, material, name)


def wall_y(y, x0, x1, material=sc.WALL, name='side'):
    """A wall in the plane y = const from x0 to x1."""
    return sc.Rectangle(((x0 + x1) / 2, y, 0.0), (1, 0, 0), (0, 0, 1), x1 - x0, 40.0, material, name)


def scene_of(*rects):
    s = sc.Scene('hand_made')
    s.extend(rects)
    s.scanner_pose = sc.Pose((0.0, 0.0, 0.0))
    return s


def horizontal_fan(degrees):
    a = np.radians(np.asarray(degrees, float))
    return np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=1)


# A sensitive scanner like the 64-ring lidar: a 10 % target is seen out to 20 m.
SENSITIVE = dict(detection_reflectivity=0.1, detection_range=20.0)


def test_a_pane_reflects_more_towards_grazing_incidence():
    angles = np.radians(np.arange(0.0, 90.0, 1.0))
    r = pane_reflectance(np.cos(angles), 1.52)
    assert 0.075 < r[0] < 0.09                      # two surfaces of 4 % each
    assert np.all(np.diff(r) >= -1e-12)             # never less as the incidence grows
    assert r[60] < 0.2 and r[80] > 0.4 and pane_reflectance(np.cos(np.radians(89.9)), 1.52) > 0.95


def test_one_pane_gives_surface_echoes_points_behind_it_and_phantoms_in_the_same_sweep():
    """A glass wall 2 m ahead (x = 2, 10 m wide), a wall 3 m behind it; in front of it side walls 4.5 m to
    each side and a wall 1 m behind the sensor: a horizontal fan of beams from -75 to 75 deg."""
    pane = sc.Rectangle((2.0, 0.0, 0.0), (0, 1, 0), (0, 0, 1), 10.0, 4.0, sc.WINDOW_GLASS, 'pane')
    azimuth = np.arange(-75.0, 75.01, 0.25)
    s = scene_of(pane, wall_x(5.0), wall_x(-1.0), wall_y(4.5, -1.0, 2.0), wall_y(-4.5, -1.0, 2.0))
    sweep = simulate_sweep(s, BeamList(horizontal_fan(azimuth), **SENSITIVE), seed=1, noise=0.0)
    gt = sweep.ground_truth
    n = sweep.num_beams
    label = gt['label']
    beam_azimuth = np.abs(np.r_[azimuth, azimuth])
    surface = label == Label.TRANSPARENT_SURFACE
    phantom = label == Label.BEHIND_REFLECTIVE
    behind = label == Label.BEHIND_TRANSPARENT
    assert surface.sum() >= 5 and phantom.sum() >= 20 and behind.sum() >= 300
    # Surface echoes only near perpendicular incidence; phantoms where the beam meets the pane obliquely.
    assert beam_azimuth[surface].max() < 6.0
    assert np.median(beam_azimuth[phantom]) > 40.0
    # ... and the glass reflects more the more obliquely it is hit: more beams show a phantom.
    steep, oblique = (np.abs(azimuth) < 30), (np.abs(azimuth) > 50) & (np.abs(azimuth) < 66)
    has_phantom = phantom[:n] | phantom[n:]
    assert has_phantom[oblique].mean() > has_phantom[steep].mean() + 0.5
    # Phantoms really lie in front of the pane (the mirrored side), points behind it behind.
    assert (true_xyz(gt[phantom])[:, 0] < 2.0).all() and (true_xyz(gt[behind])[:, 0] > 2.0).all()
    assert (gt['object_id'][phantom | behind | surface] == 0).all()
    # A beam may hold a transmitted point and a phantom at once: the pane transmits and reflects.
    both = (behind[:n] & phantom[n:]) | (phantom[:n] & behind[n:])
    assert both.sum() > 5


def intensities(rects, directions, **kwargs):
    """The noise-free returns of hand-made beams from the origin (physics.trace, realistic)."""
    params = PhysicsParams()
    return trace(SceneArrays(scene_of(*rects)), np.zeros(3), np.asarray(directions, float), 50.0, params,
                 min_intensity=kwargs.get('min_intensity', 1e-3))


def test_mirror_peak_is_sharp_and_saturates_glass_is_weaker_and_a_wall_is_lambertian():
    azimuth = np.array([0.0, 2.0, 5.0, 20.0, 40.0])
    directions = horizontal_fan(azimuth)
    for material, kind in ((sc.MIRROR_GLASS, Label.REFLECTIVE_SURFACE), (sc.WINDOW_GLASS, Label.TRANSPARENT_SURFACE)):
        panel = sc.panel((2.0, 0.0, 0.0), 180.0, 6.0, 6.0, material)
        r = intensities([panel], directions)
        surf = r.label == kind
        by_beam = np.zeros(len(azimuth))
        by_beam[r.beam[surf]] = r.intensity[surf]
        if material is sc.MIRROR_GLASS:
            mirror = by_beam
        else:
            glass = by_beam
    # The specular peak: > 100 white walls at 2 m straight on, a hundredth of that 5 deg off.
    white = GAIN / 4.0
    assert mirror[0] > 100 * white and mirror[2] < mirror[0] / 100
    assert mirror[0] > glass[0] > 0 and glass[1] < glass[0] / 2
    # Off the peak only the haze: faint, falling with cos(incidence).
    # (haze cos(i) / range^2 with range = 2 m / cos(i): cos^3)
    np.testing.assert_allclose(mirror[4] / mirror[3], (math.cos(math.radians(40)) / math.cos(math.radians(20))) ** 3,
                               rtol=1e-6)
    assert mirror[3] < 0.02 * white and glass[3] < mirror[3]
    # A white wall: albedo cos(i) / range^2 (range = 2 / cos(i) on a plane at x = 2).
    r = intensities([wall_x(2.0)], directions)
    expected = GAIN * 0.7 * np.cos(np.radians(azimuth)) ** 3 / 4.0
    np.testing.assert_allclose(r.intensity[np.argsort(r.beam)], expected, rtol=1e-9)
    # The scanner saturates: nothing above 3 white walls at 1 m.
    sweep = simulate_sweep(scene_of(sc.panel((2.0, 0.0, 0.0), 180.0, 6.0, 6.0, sc.MIRROR_GLASS)),
                           scanner.preset('hesai_qt64'), seed=0)
    assert np.nanmax(sweep.echo1['intensity']) <= 3 * GAIN


def test_shiny_metal_returns_its_surface_at_every_incidence_and_reflects_a_dimmer_phantom():
    metal = sc.panel((2.0, 0.0, 0.0), 180.0, 6.0, 6.0, sc.SHINY_METAL)
    mirror = sc.panel((2.0, 0.0, 0.0), 180.0, 6.0, 6.0, sc.MIRROR_GLASS)
    directions = horizontal_fan([0.0, 30.0, 50.0])
    found = {}
    for name, panel in (('metal', metal), ('mirror', mirror)):
        r = intensities([panel, wall_x(-3.0), wall_y(8.0, -3.0, 2.0)], directions)
        found[name] = r
    m = found['metal']
    surface_beams = set(m.beam[m.label == Label.REFLECTIVE_SURFACE].tolist())
    assert surface_beams == {0, 1, 2}
    phantom = m.label == Label.BEHIND_REFLECTIVE
    assert set(m.beam[phantom].tolist()) == {0, 1, 2}
    mirror_phantom = found['mirror'].label == Label.BEHIND_REFLECTIVE
    # Two-way through a reflectance of 0.5 instead of 0.9: (0.5 / 0.9)^2 of the mirror's phantom.
    ratio = m.intensity[phantom][np.argsort(m.beam[phantom])] / \
        found['mirror'].intensity[mirror_phantom][np.argsort(found['mirror'].beam[mirror_phantom])]
    np.testing.assert_allclose(ratio, (0.5 / 0.9) ** 2, rtol=1e-9)


def plain_lidar(**overrides):
    values = dict(rings=9, azimuth_steps=1200, vertical_fov_deg=(-4.0, 4.0), min_range=0.1, max_range=60.0,
                  range_noise=0.0, range_noise_far=0.0, beam_divergence_deg=0.5, echo_separation=0.9,
                  return_mode='last_strongest', detection_reflectivity=0.1, detection_range=20.0)
    values.update(overrides)
    return DualReturnLidar(**values)


def box_scene(box_x, wall_x_at):
    s = scene_of(wall_x(wall_x_at))
    s.extend(sc.box((box_x + 0.25, 0.0), (0.5, 1.0), 4.0, sc.WOOD, z0=-2.0))
    return s


def test_mixed_pixels_give_double_echoes_at_the_depth_edges_of_plain_geometry():
    """A box 3 m ahead, 1 m wide, a wall 6 m ahead: footprints across the box's sides see both."""
    sweep = simulate_sweep(box_scene(3.0, 6.0), plain_lidar(), seed=0)
    gt = sweep.ground_truth
    n = sweep.num_beams
    double = gt['double_echo'][:n].astype(bool)
    assert double.sum() >= 9   # at least one per ring
    assert set(np.unique(gt['label'][np.r_[double, double]])) == {Label.VALID}
    assert sweep.objects == []
    # Only beams whose footprint straddles a side of the box: azimuth within the footprint of atan(0.5 / 3).
    azimuth = np.degrees(np.arctan2(gt['y'][:n], gt['x'][:n]))[double]
    edge = math.degrees(math.atan2(0.5, 3.0))
    assert np.all(np.abs(np.abs(azimuth) - edge) < 0.5)
    # Echo 1 on the box, echo 2 on the wall.
    np.testing.assert_allclose(true_xyz(gt[:n][double])[:, 0], 3.0, atol=0.02)
    np.testing.assert_allclose(true_xyz(gt[n:][double])[:, 0], 6.0, atol=0.02)


def test_a_depth_edge_closer_than_the_echo_separation_gives_one_echo_between_the_surfaces():
    """Box 3 m ahead, wall 3.5 m: the footprints across its sides merge into one echo in between."""
    sweep = simulate_sweep(box_scene(3.0, 3.5), plain_lidar(), seed=0)
    gt = sweep.ground_truth
    n = sweep.num_beams
    assert not gt['double_echo'].any()
    x = xyz(gt[:n])[:, 0]
    between = (x > 3.05) & (x < 3.45)
    assert between.sum() >= 9
    assert set(np.unique(gt['label'][:n][between])) == {Label.VALID}
    # Thin beams (ideal physics) see either the box or the wall.
    ideal = simulate_sweep(box_scene(3.0, 3.5), plain_lidar(), seed=0, physics=PhysicsParams.ideal())
    x = xyz(ideal.ground_truth[:n])[:, 0]
    assert not ((x > 3.05) & (x < 3.45)).any()


def test_the_second_return_is_stored_only_where_it_differs_from_the_first():
    """Glass with a wall 0.5 m behind: one echo (the lidar cannot separate them); 1.5 m behind: two."""
    for gap, echoes in ((0.5, 1), (1.5, 2)):
        pane = sc.Rectangle((2.0, 0.0, 0.0), (0, 1, 0), (0, 0, 1), 3.0, 3.0, sc.WINDOW_GLASS, 'pane')
        s = scene_of(pane, wall_x(2.0 + gap))
        lidar = plain_lidar(rings=1, azimuth_steps=3600, vertical_fov_deg=(0.0, 0.0))
        sweep = simulate_sweep(s, lidar, seed=0)
        straight = 0   # azimuth 0: perpendicular to the pane, its surface echo is strong
        gt = sweep.ground_truth
        assert int(gt['double_echo'][straight]) == (echoes == 2)
        cloud, _, (echo, beam) = dual_return_arrays(sweep)
        assert (beam == straight).sum() == echoes
        # The stored returns differ by at least the echo separation wherever there are two.
        p1, p2 = xyz(sweep.echo1), xyz(sweep.echo2)
        two = gt['double_echo'][:sweep.num_beams].astype(bool)
        gaps = np.linalg.norm(p2[two], axis=1) - np.linalg.norm(p1[two], axis=1)
        assert (gaps >= 0.9 - 1e-6).all()
        assert len(cloud) == np.isfinite(p1).all(axis=1).sum() + two.sum()


def test_the_reported_echoes_follow_the_return_mode():
    # Beam 0: four echoes (range, intensity) (1, 5) (2, 9) (3, 7) (4, 1); beam 1: (1, 1) (2, 2) (3, 9),
    # the last the strongest; beam 2: one echo.
    beam = np.array([0, 0, 0, 0, 1, 1, 1, 2])
    measured = np.array([1.0, 2.0, 3.0, 4.0, 1.0, 2.0, 3.0, 5.0])
    intensity = np.array([5.0, 9.0, 7.0, 1.0, 1.0, 2.0, 9.0, 3.0])

    def ranges(mode, max_echoes=0):
        near, far = reported_echoes(beam, measured, intensity, mode, max_echoes)
        return measured[near].tolist(), measured[far].tolist()

    assert ranges('first_last') == ([1, 1, 5], [4, 3, 5])
    assert ranges('first_last', 3) == ([1, 1, 5], [3, 3, 5])            # the Hokuyo reports 3 echoes at most
    assert ranges('last_strongest') == ([2, 2, 5], [4, 3, 5])          # last strongest: the second strongest
    assert ranges('strongest_two') == ([2, 2, 5], [3, 3, 5])
    with pytest.raises(ValueError):
        reported_echoes(beam, measured, intensity, 'all', 0)


def elevations_and_azimuths(s):
    d = s.directions().reshape(s.rows, s.cols, 3)
    return np.degrees(np.arcsin(d[..., 2])), np.degrees(np.arctan2(d[..., 1], d[..., 0])) % 360


@pytest.mark.parametrize('name, rings, columns, low, high, step', [
    ('hesai_qt64', 64, 600, -52.0, 52.0, 0.6),
    ('ouster_os0_128', 128, 2048, -45.0, 45.0, 360 / 2048),
    ('velodyne_hdl32e', 32, 2250, -30.67, 10.67, 0.16),
])
def test_lidar_presets_have_their_data_sheet_geometry(name, rings, columns, low, high, step):
    s = scanner.preset(name)
    assert (s.rows, s.cols, s.family) == (rings, columns, name)
    el, az = elevations_and_azimuths(s)
    np.testing.assert_allclose(el[:, 0], np.linspace(low, high, rings), atol=1e-9)
    np.testing.assert_allclose(np.diff(az[0]), step, atol=1e-9)
    assert s.return_mode in scanner.RETURN_MODES and s.echo_separation > 0 and s.beam_divergence_deg > 0
    if name == 'velodyne_hdl32e':
        np.testing.assert_allclose(np.diff(el[:, 0]), 1.3342, atol=1e-3)
    if name == 'hesai_qt64':
        assert s.echo_separation == pytest.approx(0.9) and (s.min_range, s.max_range) == (0.1, 60.0)
        assert s.return_mode == 'last_strongest'
    if name == 'ouster_os0_128':
        assert s.return_mode == 'strongest_two' and s.min_range == 0.3


def test_hokuyo_preset_and_its_range_noise():
    for scans in (100, 1000):
        s = scanner.preset('hokuyo_utm30lx_ew', scans=scans)
        assert (s.rows, s.cols) == (scans, 1080)
        np.testing.assert_allclose(np.degrees(s.grid_steps()), [180.0 / scans, 0.25])
    s = scanner.preset('hokuyo_utm30lx_ew')
    assert (s.min_range, s.max_range, s.return_mode, s.max_echoes) == (0.1, 30.0, 'first_last', 3)
    np.testing.assert_allclose(scanner.range_sigma(s, [5.0, 15.0]), [0.01, 0.017])
    # The noise of a simulated sweep: a wall at 5 m and one at 15 m.
    lidar = BeamList(horizontal_fan(np.zeros(4000)) * 1.0, range_noise=s.range_noise)
    lidar.range_noise_far, lidar.range_noise_far_from = s.range_noise_far, s.range_noise_far_from
    for distance, sigma in ((5.0, 0.01), (15.0, 0.017)):
        sweep = simulate_sweep(scene_of(wall_x(distance)), lidar, seed=3)
        error = np.linalg.norm(xyz(sweep.echo1), axis=1) - distance
        assert abs(error.std() - sigma) < 0.1 * sigma
    with pytest.raises(KeyError):
        scanner.preset('no_such_sensor')


def test_a_dark_wall_is_seen_out_to_the_data_sheet_range():
    """The 64-ring lidar sees a 10 % target out to 20 m, no farther."""
    dark = sc.Material('dark', albedo=0.1)
    lidar = scanner.preset('hesai_qt64', range_noise=0.0, range_noise_far=0.0)
    for distance, seen in ((19.5, True), (20.5, False)):
        sweep = simulate_sweep(scene_of(wall_x(distance, dark, size=100.0)), lidar, seed=0)
        d = lidar.directions()
        straight = np.argmax(d[:, 0])   # the beam nearest to +x: perpendicular incidence
        assert np.isfinite(sweep.echo1['x'][straight]) == seen
