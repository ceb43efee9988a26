"""Beam tracing on geometry whose answer is known by hand: the ideal model (PhysicsParams.ideal(), the
simulator before issue 14, which pinned tests still use) exactly, and the ground-truth layout of both
models. The realistic model: test_physics_realistic.py."""
import math
from dataclasses import replace

import numpy as np
import pytest

from ohm_mirror_detector3d import scene as sc
from ohm_mirror_detector3d.labels import Label
from ohm_mirror_detector3d.physics import PhysicsParams
from ohm_mirror_detector3d.scanner import BeamList, RotatingHokuyo
from ohm_mirror_detector3d.simulate import simulate_sweep, true_xyz, xyz

IDEAL = PhysicsParams.ideal()


def wall_x(x, material=sc.WALL, size=20.0, name='wall'):
    """A big wall in the plane x = const."""
    return sc.Rectangle((x, 0.0, 0.0), (0, 1, 0), (0, 0, 1), size, size, material, name)


def scene_of(*rects):
    s = sc.Scene('hand_made')
    s.extend(rects)
    s.scanner_pose = sc.Pose((0.0, 0.0, 0.0))
    return s


def echoes(sweep):
    n = sweep.num_beams
    gt = sweep.ground_truth
    return xyz(gt[:n]), xyz(gt[n:]), gt[:n], gt[n:]


def test_perpendicular_mirror_gives_surface_echo_and_phantom_at_the_mirrored_hit():
    d, w = 2.0, 3.0
    mirror = sc.panel((d, 0.0, 0.0), 180.0, 0.6, 0.4, sc.MIRROR_GLASS)  # faces the scanner (-x)
    s = scene_of(mirror, wall_x(-w))
    sweep = simulate_sweep(s, BeamList([[1, 0, 0]]), noise=0.0, physics=IDEAL)
    p1, p2, g1, g2 = echoes(sweep)
    np.testing.assert_allclose(p1[0], [d, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p2[0], [d + d + w, 0, 0], atol=1e-9)  # path d out, d + w back
    assert g1['label'][0] == Label.REFLECTIVE_SURFACE and g2['label'][0] == Label.BEHIND_REFLECTIVE
    assert g1['object_id'][0] == 0 and g2['object_id'][0] == 0
    np.testing.assert_allclose(true_xyz(g2)[0], [-w, 0, 0], atol=1e-6)
    np.testing.assert_allclose(true_xyz(g1)[0], [d, 0, 0], atol=1e-6)


def test_oblique_mirror_beyond_the_incidence_limit_gives_only_the_phantom():
    # Mirror at x = 2 turned 45 deg: a beam along +x is reflected to +y and hits a wall at y = 3.
    mirror = sc.panel((2.0, 0.0, 0.0), 135.0, 0.6, 0.4, sc.MIRROR_GLASS)
    wall = sc.Rectangle((0.0, 3.0, 0.0), (1, 0, 0), (0, 0, 1), 20, 20, sc.WALL)
    sweep = simulate_sweep(scene_of(mirror, wall), BeamList([[1, 0, 0]]), noise=0.0, physics=IDEAL)
    p1, p2, g1, g2 = echoes(sweep)
    np.testing.assert_allclose(p1[0], [5.0, 0, 0], atol=1e-9)
    np.testing.assert_array_equal(p1, p2)  # single return repeated as echo 2
    assert g1['label'][0] == Label.BEHIND_REFLECTIVE
    np.testing.assert_allclose(true_xyz(g1)[0], [2.0, 3.0, 0.0], atol=1e-6)


def test_oblique_beam_through_glass_returns_only_the_point_behind():
    pane = sc.Rectangle((2.0, 0.0, 0.0), (0, 1, 0), (0, 0, 1), 4.0, 4.0, sc.WINDOW_GLASS)
    angle = math.radians(30.0)
    beams = [[math.cos(angle), math.sin(angle), 0.0], [1.0, 0.0, 0.0]]
    sweep = simulate_sweep(scene_of(pane, wall_x(5.0)), BeamList(beams), noise=0.0, physics=IDEAL)
    p1, p2, g1, g2 = echoes(sweep)
    # Oblique: one return, on the wall behind, labelled behindTransparent of the pane.
    expected = np.array(beams[0]) * 5.0 / math.cos(angle)
    np.testing.assert_allclose(p1[0], expected, atol=1e-9)
    np.testing.assert_array_equal(p1[0], p2[0])
    assert g1['label'][0] == Label.BEHIND_TRANSPARENT and g1['object_id'][0] == 0
    # Perpendicular: surface echo on the pane, then the wall.
    np.testing.assert_allclose(p1[1], [2.0, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p2[1], [5.0, 0, 0], atol=1e-9)
    assert g1['label'][1] == Label.TRANSPARENT_SURFACE and g2['label'][1] == Label.BEHIND_TRANSPARENT


def test_glass_partial_reflection_is_off_by_default_and_gives_a_phantom_when_on():
    glass = sc.Material('half_mirror', kind=sc.GLASS, surface_echo_max_incidence_deg=4.0, reflectance=0.5,
                        transmission=0.5)
    pane = sc.Rectangle((2.0, 0.0, 0.0), (0, 1, 0), (0, 0, 1), 4.0, 4.0, glass)
    sweep = simulate_sweep(scene_of(pane, wall_x(5.0), wall_x(-3.0)), BeamList([[1, 0, 0]]), noise=0.0, physics=IDEAL)
    p1, p2, g1, g2 = echoes(sweep)
    # Three returns (surface 2 m, wall behind 5 m, reflected wall 2 + 5 = 7 m): the scanner keeps first and last.
    np.testing.assert_allclose(p1[0], [2, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p2[0], [7, 0, 0], atol=1e-9)
    assert g2['label'][0] == Label.BEHIND_REFLECTIVE
    np.testing.assert_allclose(true_xyz(g2)[0], [-3, 0, 0], atol=1e-6)


def test_two_mirrors_reflect_twice_and_the_phantom_keeps_the_first_mirror():
    # A: x = 2, turned 45 deg (+x -> +y); B: at y = 3, turned to send +y -> +x; wall at x = 5.
    a = sc.panel((2.0, 0.0, 0.0), 135.0, 0.6, 0.4, sc.MIRROR_GLASS)
    b = sc.panel((2.0, 3.0, 0.0), -45.0, 0.6, 0.4, sc.MIRROR_GLASS)
    sweep = simulate_sweep(scene_of(a, b, wall_x(5.0)), BeamList([[1, 0, 0]]), noise=0.0, physics=IDEAL)
    p1, p2, g1, g2 = echoes(sweep)
    np.testing.assert_allclose(p1[0], [2 + 3 + 3, 0, 0], atol=1e-9)
    np.testing.assert_allclose(true_xyz(g1)[0], [5, 3, 0], atol=1e-6)
    assert g1['label'][0] == Label.BEHIND_REFLECTIVE and g1['object_id'][0] == 0


def test_bounce_limit_ends_a_beam_between_facing_mirrors():
    a = sc.panel((2.0, 0.0, 0.0), 180.0, 0.6, 0.4, sc.MIRROR_GLASS)
    b = sc.panel((-2.0, 0.0, 0.0), 0.0, 0.6, 0.4, sc.MIRROR_GLASS)
    from ohm_mirror_detector3d.simulate import SweepSimulator
    sim = SweepSimulator(scene_of(a, b), BeamList([[1, 0, 0]]), PhysicsParams.ideal(max_bounces=3))
    p1, p2, g1, g2 = echoes(sim.sweep(noise=0.0))
    # Surface of a (2 m); its phantoms: surface of b at 6 m, of a at 10 m, of b at 14 m; then the limit.
    np.testing.assert_allclose(p1[0], [2, 0, 0], atol=1e-9)
    np.testing.assert_allclose(p2[0], [14, 0, 0], atol=1e-9)
    assert g2['label'][0] == Label.BEHIND_REFLECTIVE and g2['object_id'][0] == 0


def test_back_of_a_mirror_is_diffuse():
    mirror = sc.panel((2.0, 0.0, 0.0), 0.0, 0.6, 0.4, sc.MIRROR_GLASS)  # faces away from the scanner
    sweep = simulate_sweep(scene_of(mirror, wall_x(-3.0)), BeamList([[1, 0, 0]]), noise=0.0, physics=IDEAL)
    p1, p2, g1, _ = echoes(sweep)
    np.testing.assert_allclose(p1[0], [2, 0, 0], atol=1e-9)
    np.testing.assert_array_equal(p1, p2)
    assert g1['label'][0] == Label.VALID and g1['object_id'][0] == -1


def test_out_of_range_and_missing_returns_are_nan_in_both_echoes():
    sweep = simulate_sweep(scene_of(wall_x(40.0, size=200)), BeamList([[1, 0, 0], [-1, 0, 0]]), noise=0.0)
    p1, p2, g1, g2 = echoes(sweep)
    assert np.isnan(p1).all() and np.isnan(p2).all()
    assert (g1['label'] == Label.NAN_POINT).all() and (g2['label'] == Label.NAN_POINT).all()
    assert np.isnan(sweep.echo1['x']).all() and np.isnan(sweep.echo2['intensity']).all()


@pytest.fixture(scope='module', params=['ideal', 'realistic'])
def experiment1_sweeps(request, experiment1_sweep, experiment1_sweep_noiseless):
    """(noisy, noiseless) experiment1 sweeps at r = 200 under each physics model."""
    if request.param == 'realistic':
        return experiment1_sweep, experiment1_sweep_noiseless
    scanner = RotatingHokuyo(scans=200)
    return (simulate_sweep('experiment1', scanner, seed=7, physics=IDEAL),
            simulate_sweep('experiment1', replace(scanner, range_noise=0.0), seed=7, physics=IDEAL))


def test_phantom_true_position_is_the_measured_point_mirrored_across_the_mirror_plane(experiment1_sweeps):
    sweep = experiment1_sweeps[1]
    gt = sweep.ground_truth
    plane = sweep.objects[0]['plane']
    phantom = (gt['label'] == Label.BEHIND_REFLECTIVE) & (gt['object_id'] == 0)
    assert phantom.sum() > 100
    p = xyz(gt[phantom])
    dist = p @ plane[:3] + plane[3]
    assert (dist < 0).all()  # behind the mirror, seen from the scanner
    mirrored = p - 2 * dist[:, None] * plane[:3]
    error = np.linalg.norm(mirrored - true_xyz(gt[phantom]), axis=1)
    if sweep.info['physics'] == 'ideal':
        assert error.max() < 3.5e-5
    else:
        # Where a beam's footprint is traced with several rays, the echo is at their weighted range
        # and its true point their weighted hit: within the footprint (0.25 deg at <= 8 m path).
        assert np.median(error) < 1e-4 and error.max() < 0.04


def test_ground_truth_labels_are_consistent_with_positions(experiment1_sweeps):
    sweep = experiment1_sweeps[0]
    gt = sweep.ground_truth
    measured, truth = xyz(gt), true_xyz(gt)
    valid = gt['label'] == Label.VALID
    # Real points: measured = true + range noise along the ray.
    err = np.linalg.norm(measured[valid] - truth[valid], axis=1)
    ray = measured[valid] / np.linalg.norm(measured[valid], axis=1, keepdims=True)
    off_ray = np.linalg.norm(np.cross(ray, truth[valid]), axis=1)
    assert 0.006 < np.sqrt(np.mean(np.minimum(err, 0.06) ** 2)) < 0.014
    if sweep.info['physics'] == 'ideal':
        assert err.max() < 6 * 0.01
        np.testing.assert_allclose(off_ray, 0, atol=2e-4)
    else:
        # Mixed pixels: a footprint across a depth edge closer than the echo separation (0.3 m)
        # gives one echo between the two surfaces; the rest is range noise.
        assert np.mean(err < 6 * 0.017) > 0.995 and err.max() < 0.3 + 6 * 0.017
        assert np.mean(off_ray < 2e-4) > 0.99
    # Surface echoes lie on their object's plane.
    surf = gt['label'] == Label.REFLECTIVE_SURFACE
    plane = sweep.objects[0]['plane']
    np.testing.assert_allclose(truth[surf] @ plane[:3] + plane[3], 0, atol=1e-5)
    # Echo 1 is never farther than echo 2; no-return entries are NaN everywhere.
    n = sweep.num_beams
    r1, r2 = np.linalg.norm(measured[:n], axis=1), np.linalg.norm(measured[n:], axis=1)
    both = np.isfinite(r1) & np.isfinite(r2)
    assert (r1[both] <= r2[both]).all()
    nan = gt['label'] == Label.NAN_POINT
    assert np.isnan(measured[nan]).all() and np.isnan(truth[nan]).all() and (gt['object_id'][nan] == -1).all()
    assert set(np.unique(gt['label'])) <= {Label.VALID, Label.REFLECTIVE_SURFACE, Label.BEHIND_REFLECTIVE,
                                           Label.TRANSPARENT_SURFACE, Label.BEHIND_TRANSPARENT, Label.NAN_POINT}
    assert (gt['echo'][:n] == 1).all() and (gt['echo'][n:] == 2).all()
    np.testing.assert_array_equal(gt['beam'][:n], np.arange(n))
    # double_echo marks both entries of exactly the beams with two distinct echoes.
    two = both & (r1 != r2)
    np.testing.assert_array_equal(gt['double_echo'][:n].astype(bool), two)
    np.testing.assert_array_equal(gt['double_echo'][n:], gt['double_echo'][:n])


def test_echo_clouds_match_the_ground_truth_and_ranges_respect_the_gate(experiment1_sweep):
    sweep = experiment1_sweep
    n = sweep.num_beams
    gt = sweep.ground_truth
    np.testing.assert_array_equal(xyz(sweep.echo1), xyz(gt[:n]))
    np.testing.assert_array_equal(xyz(sweep.echo2), xyz(gt[n:]))
    r = np.linalg.norm(xyz(sweep.echo1), axis=1)
    r = r[np.isfinite(r)]
    assert r.min() >= 0.1 and r.max() <= 30.0
    inten = sweep.echo1['intensity'][np.isfinite(sweep.echo1['x'])]
    assert (inten > 0).all()


def test_determinism_under_a_seed():
    a = simulate_sweep('mirror_and_glass', RotatingHokuyo(scans=40), seed=5)
    b = simulate_sweep('mirror_and_glass', RotatingHokuyo(scans=40), seed=5)
    c = simulate_sweep('mirror_and_glass', RotatingHokuyo(scans=40), seed=6)
    assert a.ground_truth.tobytes() == b.ground_truth.tobytes()
    assert a.echo1.tobytes() == b.echo1.tobytes() and a.echo2.tobytes() == b.echo2.tobytes()
    assert a.ground_truth.tobytes() != c.ground_truth.tobytes()
    # Only the noise differs between seeds.
    np.testing.assert_array_equal(a.ground_truth['label'], c.ground_truth['label'])
