"""Vectorised beam tracing through a scene of rectangles: every return a beam produces.

Beams are traced in chunks (numpy over rays x rectangles, no Python loop over
rays). Each step intersects all live rays with the rectangles, takes the
nearest hit and applies the material; reflected and transmitted rays continue
in the next step. A return's range is the total path length from the scanner,
and the scanner puts it along the *original* beam direction: a return after a
reflection is a phantom at range = path length, behind the mirror. Its true
position is the point actually hit. Returns beyond `max_range` of path length
are lost. The rays of a step are grouped by the surface they leave and their
direction, and each group is tested only against the rectangles whose
bounding spheres its bundle of rays can reach.

Two material models (`PhysicsParams.model`):

**realistic** (the default). Energy: a ray carries the one-way share E of the
beam's power it still has (the product of the reflectances and transmissions
met so far); the light comes back the same way, so a return's intensity is
proportional to E^2.

* diffuse surface (or the back of a mirror or metal panel): Lambertian,
  `gain * E^2 * albedo * cos(incidence) / max(range, 1 m)^2`; the ray ends.
* mirror front: reflects `reflectance` (0.9) at every incidence. Its surface
  echo is a specular peak plus a faint diffuse haze:
  `gain * E^2 * (haze * cos(i) + R * lobe(i)) / max(range, 1 m)^2` with
  `lobe(i) = exp(-2 i^2 / s^2) / (2 s^2)`, s = `specular_lobe_deg` in radians:
  light reflected specularly into a Gaussian cone of spread s, seen from the
  scanner at 2 i off its axis, relative to a white Lambertian surface. At
  perpendicular incidence a mirror (s = 2 deg) returns ~370 times a white
  wall, far above the scanner's saturation: a sharp, saturated peak; beyond a
  few degrees only the haze (1 %) is left, which the scanner detects within a
  few metres only.
* glass (both sides alike): a pane of refractive index n reflects, per
  polarisation, `R = 2 r / (1 + r)` of the light (Fresnel's r of one surface,
  both surfaces, incoherent multiple reflections; unpolarised: the mean), and
  transmits 1 - R: 8 % reflected at perpendicular incidence, 16 % at 60 deg,
  54 % at 80 deg, all of it at grazing incidence. Every hit splits the ray
  into a reflected and a transmitted one, so one pane yields surface echoes
  (near perpendicular: lobe s = 1.7 deg, haze 0.05 %), points behind it and
  reflected phantoms in the same sweep, phantoms mostly where the beam meets
  it obliquely and gives no surface echo.
* shiny metal front: partially specular, a diffuse return (`haze`, 0.15)
  wherever it is hit and a reflection of `reflectance` (0.5) with a broad lobe
  (8 deg), so its phantoms are dimmer than a mirror's and its surface is seen
  at every incidence, like a wall.

A ray is dropped once even a white wall could no longer return a detectable
echo along it (`gain * E^2 / path^2` below the detection threshold), or after
`max_bounces` reflections. Contributions of the rays of one beam's footprint
(simulate.py traces several rays per beam where the footprint may straddle a
depth edge) carry the ray's weight. Detection (the scanner's threshold) is
applied by simulate.py after merging a beam's contributions into echoes.

**ideal** (the simulator before issue 14; pinned tests use it): one ray per
beam, energy one-way.

* diffuse: `gain * albedo * cos(incidence) / max(range, 1 m)^2`; the ray ends.
* mirror front (and metal, as a mirror without incidence limit): if the
  incidence angle is below `surface_echo_max_incidence_deg`, a surface echo
  `gain * strength * exp(-0.5 (incidence / (limit/2))^2) / max(range, 1 m)^2`;
  in any case the ray is reflected (energy times `reflectance`).
* glass: a surface echo below the incidence limit; the ray is transmitted
  unchanged in direction (energy times `transmission`); a reflected ray is
  split off only when the material's `reflectance` > 0 (default off).
* returns below `min_intensity` are not detected.

Ground-truth label of a return (both models): a ray that has been reflected at
least once makes `behindReflective` returns (object = the first reflecting
object: its plane is the one the phantom appears behind, and back-projecting
across it undoes a single reflection); otherwise a ray that went through glass
makes `behindTransparent` returns (object = the first pane), except surface
echoes of another mirror/glass/metal object, which keep their own surface
label; a ray that met nothing special makes `valid` returns. Surface echoes of
a ray not yet reflected are `reflectiveSurface` (mirror, metal) or
`transparentSurface` (glass) of that object.
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from .labels import Label
from .scene import DIFFUSE, GLASS, METAL, MIRROR

_KIND_CODE = {DIFFUSE: 0, MIRROR: 1, GLASS: 2, METAL: 3}

# Return.surface: what made the return (the intensity noise depends on it).
SURFACE_DIFFUSE, SURFACE_MIRROR, SURFACE_GLASS, SURFACE_METAL = 0, 1, 2, 3

MODELS = ('realistic', 'ideal')


@dataclass(frozen=True)
class PhysicsParams:
    model: str = 'realistic'      # 'realistic' or 'ideal' (see the module doc)
    max_bounces: int = 4          # reflections after which a ray is dropped
    max_steps: int = 12           # surfaces a ray may meet (reflections + transmissions + final hit)
    intensity_gain: float = 8000.0
    min_intensity: float = 0.5    # ideal model: detection threshold (realistic: the scanner's)
    chunk_beams: int = 262144     # rays traced together (grouped by direction inside, see nearest_hit_culled)
    footprint_rays: int = 6       # realistic: rays on the rim of a beam's footprint at depth edges

    def __post_init__(self):
        if self.model not in MODELS:
            raise ValueError('physics model must be one of %s, not %r' % (MODELS, self.model))

    @property
    def ideal_model(self):
        return self.model == 'ideal'

    @staticmethod
    def ideal(**overrides):
        """The simulator as it was before issue 14: glass that never reflects (unless its material says
        so), surface echoes only below an incidence limit, one ray per beam (no mixed pixels), every
        distinct return kept, the nearest and farthest as the two echoes."""
        return replace(PhysicsParams(model='ideal'), **overrides)


def pane_reflectance(cos_incidence, refractive_index):
    """Share of unpolarised light a glass pane reflects (both surfaces, incoherent multiple reflections)."""
    ci = np.clip(np.asarray(cos_incidence, float), 0.0, 1.0)
    n = np.asarray(refractive_index, float)
    sin_t = np.sqrt(1.0 - ci ** 2) / n
    ct = np.sqrt(np.clip(1.0 - sin_t ** 2, 0.0, 1.0))
    with np.errstate(divide='ignore', invalid='ignore'):
        rs = ((ci - n * ct) / (ci + n * ct)) ** 2
        rp = ((ct - n * ci) / (ct + n * ci)) ** 2
    rs = np.where(ci > 0, rs, 1.0)
    rp = np.where(ci > 0, rp, 1.0)
    return 0.5 * (2 * rs / (1 + rs) + 2 * rp / (1 + rp))


def specular_lobe(incidence, lobe_rad):
    """Specular light sent back to the scanner, relative to a white Lambertian surface (module doc)."""
    s = np.maximum(lobe_rad, 1e-6)
    return np.exp(-2.0 * incidence ** 2 / s ** 2) / (2.0 * s ** 2)


class SceneArrays:
    """The scene's rectangles as arrays for vectorised intersection."""

    def __init__(self, scene):
        rects = scene.rectangles
        self.centre = np.array([r.centre for r in rects], float).reshape(-1, 3)
        self.u = np.array([r.axis_u for r in rects], float).reshape(-1, 3)
        self.v = np.array([r.axis_v for r in rects], float).reshape(-1, 3)
        self.normal = np.cross(self.u, self.v)
        self.half_w = np.array([r.width / 2 for r in rects], float)
        self.half_h = np.array([r.height / 2 for r in rects], float)
        self.radius = np.hypot(self.half_w, self.half_h)
        self.object_id = np.array([r.object_id for r in rects], np.int32)
        m = [r.material for r in rects]
        self.kind = np.array([_KIND_CODE[x.kind] for x in m], np.int8)
        self.albedo = np.array([x.albedo for x in m], float)
        self.cos_limit = np.cos(np.radians([x.surface_echo_max_incidence_deg for x in m])).reshape(-1)
        self.limit = np.radians([x.surface_echo_max_incidence_deg for x in m]).reshape(-1)
        self.strength = np.array([x.surface_echo_strength for x in m], float)
        self.reflectance = np.array([x.reflectance for x in m], float)
        self.transmission = np.array([x.transmission for x in m], float)
        self.refractive_index = np.array([x.refractive_index for x in m], float)
        self.lobe = np.radians([x.specular_lobe_deg for x in m]).reshape(-1)
        self.haze = np.array([x.haze for x in m], float)
        self.cn = np.einsum('ij,ij->i', self.centre, self.normal)
        self.cu = np.einsum('ij,ij->i', self.centre, self.u)
        self.cv = np.einsum('ij,ij->i', self.centre, self.v)

    def __len__(self):
        return len(self.cn)

    def in_cone(self, origin, axis, half_angle, max_range, origin_radius=0.0):
        """Indices of the rectangles whose bounding spheres meet the cone (apex within origin_radius of
        origin, unit axis, half angle [rad]) within max_range: the only ones a ray from there with a
        direction inside the cone can hit."""
        rel = self.centre - origin
        dist = np.linalg.norm(rel, axis=1)
        margin = self.radius + origin_radius
        with np.errstate(divide='ignore', invalid='ignore'):
            angle = np.arccos(np.clip(rel @ axis / dist, -1.0, 1.0))
            reach = np.arcsin(np.clip(margin / dist, 0.0, 1.0))
        inside = dist <= margin * (1 + 1e-9) + 1e-9
        near = dist - margin <= max_range
        return np.nonzero(inside | (near & (angle <= half_angle + reach + 1e-6)))[0]

    def nearest_hit_culled(self, origins, directions, exclude, max_range, rays_per_group=1500, min_group=96):
        """nearest_hit, with the rays grouped by the rectangle they leave and by direction, and each
        group tested only against the rectangles its bundle can reach (in_cone). Groups smaller than
        min_group are tested together against every rectangle."""
        n = len(origins)
        t_all, k_all = np.full(n, np.inf), np.full(n, -1)
        if n == 0 or len(self) == 0:
            return t_all, k_all
        tiles, n_tiles = _direction_tiles(directions, rays_per_group)
        key = (exclude.astype(np.int64) + 1) * n_tiles + tiles
        order = np.argsort(key, kind='stable')
        sorted_key = key[order]
        bounds = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1], True])
        rest = []
        for a, b in zip(bounds[:-1], bounds[1:]):
            for start in range(a, b, _MAX_GROUP):
                rays = order[start:min(b, start + _MAX_GROUP)]
                if len(rays) < min_group:
                    rest.append(rays)
                    continue
                d = directions[rays]
                axis = d.mean(axis=0)
                axis /= max(np.linalg.norm(axis), 1e-12)
                half_angle = float(np.arccos(np.clip(d @ axis, -1.0, 1.0)).max())
                o = origins[rays]
                centre = o.mean(axis=0)
                radius = float(np.sqrt(((o - centre) ** 2).sum(axis=1).max()))
                subset = self.in_cone(centre, axis, half_angle, max_range, radius) if half_angle < 1.5 else None
                t_all[rays], k_all[rays] = self.nearest_hit(o, d, exclude[rays], subset)
        if rest:
            rays = np.concatenate(rest)
            for start in range(0, len(rays), _MAX_GROUP):
                part = rays[start:start + _MAX_GROUP]
                t_all[part], k_all[part] = self.nearest_hit(origins[part], directions[part], exclude[part])
        return t_all, k_all

    def nearest_hit(self, origins, directions, exclude, subset=None):
        """Distance and index of the nearest rectangle hit by each ray (inf, -1 if none).

        exclude: per ray a rectangle index to ignore (the one the ray leaves), or -1.
        subset: rectangle indices to test (default all). The rays x rectangles test runs in
        float32 with in-place operations (it is memory bound); the distance to the chosen
        rectangle is then recomputed in float64.
        """
        n_rays = len(origins)
        idx = np.arange(len(self)) if subset is None else np.asarray(subset)
        if n_rays == 0 or len(idx) == 0:
            return np.full(n_rays, np.inf), np.full(n_rays, -1)
        f32 = np.float32
        o32, d32 = origins.astype(f32), directions.astype(f32)
        normal, u, v = self.normal[idx].T.astype(f32), self.u[idx].T.astype(f32), self.v[idx].T.astype(f32)
        with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
            denom = d32 @ normal
            t = o32 @ normal
            np.subtract(self.cn[idx].astype(f32), t, out=t)
            np.divide(t, denom, out=t)
            ok = t > 1e-6
            for axis, centre_dot, half in ((u, self.cu[idx], self.half_w[idx]), (v, self.cv[idx], self.half_h[idx])):
                a = d32 @ axis
                a *= t
                a += o32 @ axis
                a -= centre_dot.astype(f32)
                np.abs(a, out=a)
                ok &= a <= (half + 1e-5).astype(f32)
        rows = np.nonzero(exclude >= 0)[0]
        if len(rows):
            position = np.full(len(self), -1)
            position[idx] = np.arange(len(idx))
            local = position[exclude[rows]]
            keep = local >= 0
            ok[rows[keep], local[keep]] = False
        np.copyto(t, f32(np.inf), where=~ok)
        k_local = np.argmin(t, axis=1)
        hit = np.isfinite(t[np.arange(n_rays), k_local])
        k = np.where(hit, idx[k_local], -1)
        nk = self.normal[np.maximum(k, 0)]
        with np.errstate(divide='ignore', invalid='ignore'):
            t_exact = (self.cn[np.maximum(k, 0)] - np.einsum('ij,ij->i', origins, nk)) / \
                np.einsum('ij,ij->i', directions, nk)
        return np.where(hit, t_exact, np.inf), k


_FIELDS = ('beam', 'path_length', 'true_world', 'intensity', 'label', 'object_id', 'rect', 'surface')


@dataclass
class Returns:
    """All returns of a set of beams (unordered): one entry per return (or, realistic, per contribution
    of one ray of a beam's footprint)."""
    beam: np.ndarray        # int64, index of the beam
    path_length: np.ndarray  # float64, total path length = range the scanner measures (before noise)
    true_world: np.ndarray  # (n, 3) float64, the point actually hit, world frame
    intensity: np.ndarray   # float64
    label: np.ndarray       # uint8 Label
    object_id: np.ndarray   # int32, -1 none
    rect: np.ndarray        # int32, index of the rectangle hit
    surface: np.ndarray     # uint8, SURFACE_*: a diffuse hit or the surface echo of a mirror/glass/metal

    @staticmethod
    def empty():
        return Returns(np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.uint8),
                       np.zeros(0, np.int32), np.zeros(0, np.int32), np.zeros(0, np.uint8))

    @staticmethod
    def concatenate(parts):
        parts = [Returns.empty()] + list(parts)
        return Returns(*(np.concatenate([getattr(p, f) for p in parts]) for f in _FIELDS))

    def select(self, index):
        """The returns at `index` (a mask or indices)."""
        return Returns(*(getattr(self, f)[index] for f in _FIELDS))

    def __len__(self):
        return len(self.beam)


_MAX_GROUP = 16384   # rays per nearest_hit call (memory ~ rays x rectangles)


def _direction_tiles(directions, rays_per_tile):
    """(tile index of each direction, number of tiles): cube-map faces split into m x m cells, m
    chosen so that a tile holds about rays_per_tile rays."""
    n = len(directions)
    m = int(np.clip(round(math.sqrt(n / (6.0 * rays_per_tile))), 1, 16))
    a = np.abs(directions)
    rows = np.arange(n)
    face_axis = np.argmax(a, axis=1)
    major = np.maximum(a[rows, face_axis], 1e-12)
    sign = directions[rows, face_axis] < 0
    others = np.array([[1, 2], [0, 2], [0, 1]])[face_axis]
    s = directions[rows, others[:, 0]] / major
    t = directions[rows, others[:, 1]] / major
    cs = np.clip(((s + 1) / 2 * m).astype(int), 0, m - 1)
    ct = np.clip(((t + 1) / 2 * m).astype(int), 0, m - 1)
    return ((face_axis * 2 + sign) * m + cs) * m + ct, 6 * m * m


def trace(scene_arrays, origin, directions, max_range, params=PhysicsParams(), beam_offset=0, beams=None,
          weights=None, min_intensity=None):
    """Traces rays from one origin (3,) along unit directions (n, 3) in the world frame.

    Returns every return of every ray (Returns). Beam indices are `beams` (one per ray) or else
    beam_offset + row index of `directions`. Realistic model: `weights` (one per ray, default 1)
    scale the contributions (the rays of one beam's footprint share its power), and
    `min_intensity` (the scanner's detection threshold) decides which rays are worth following;
    nothing is dropped for being faint (simulate.py detects after merging). Ideal model: returns
    below params.min_intensity are dropped.
    """
    origin = np.asarray(origin, float)
    directions = np.asarray(directions, float)
    n = len(directions)
    beams = np.arange(n, dtype=np.int64) + beam_offset if beams is None else np.asarray(beams, np.int64)
    weights = np.ones(n) if weights is None else np.broadcast_to(np.asarray(weights, float), (n,))
    threshold = params.min_intensity if min_intensity is None else min_intensity
    parts = []
    for start in range(0, n, params.chunk_beams):
        rays = slice(start, start + params.chunk_beams)
        parts.append(_trace_chunk(scene_arrays, origin, directions[rays], max_range, params, beams[rays],
                                  weights[rays], threshold))
    return Returns.concatenate(parts)


def _trace_chunk(sa, origin, directions, max_range, params, beam, weight, threshold):
    n = len(directions)
    o = np.broadcast_to(origin, (n, 3)).copy()
    d = directions.astype(float)
    travelled = np.zeros(n)
    energy = np.ones(n)
    reflector = np.full(n, -1, np.int32)   # object id of the first reflecting object
    pane = np.full(n, -1, np.int32)        # object id of the first glass passed
    bounces = np.zeros(n, np.int32)
    exclude = np.full(n, -1)
    out = []
    respond = _ideal_response if params.ideal_model else _realistic_response

    for _ in range(params.max_steps):
        if len(beam) == 0:
            break
        t, k = sa.nearest_hit_culled(o, d, exclude, max_range)
        alive = (k >= 0) & (travelled + t <= max_range)
        beam, o, d, t, k, weight = beam[alive], o[alive], d[alive], t[alive], k[alive], weight[alive]
        travelled, energy, reflector, pane, bounces = (travelled[alive], energy[alive], reflector[alive],
                                                       pane[alive], bounces[alive])
        if len(beam) == 0:
            break
        hit = o + t[:, None] * d
        path = travelled + t
        cos_signed = np.einsum('ij,ij->i', d, sa.normal[k])     # < 0: hit from the front side
        cos_inc = np.abs(cos_signed)
        incidence = np.arccos(np.clip(cos_inc, 0.0, 1.0))
        falloff = params.intensity_gain * weight / np.maximum(path, 1.0) ** 2
        kind = sa.kind[k]
        obj = sa.object_id[k]
        front = cos_signed < 0
        was_reflected = reflector >= 0
        behind_label = np.where(was_reflected, Label.BEHIND_REFLECTIVE,
                                np.where(pane >= 0, Label.BEHIND_TRANSPARENT, Label.VALID)).astype(np.uint8)
        behind_obj = np.where(was_reflected, reflector, np.where(pane >= 0, pane, -1)).astype(np.int32)

        diffuse_intensity, surface, surface_intensity, reflected, reflect_energy, transmit_energy = respond(
            sa, k, kind, front, cos_inc, incidence, falloff, energy)
        diffuse = ~np.isnan(diffuse_intensity)
        out.append(Returns(beam[diffuse], path[diffuse], hit[diffuse], diffuse_intensity[diffuse],
                           behind_label[diffuse], behind_obj[diffuse], k[diffuse].astype(np.int32),
                           np.full(int(diffuse.sum()), SURFACE_DIFFUSE, np.uint8)))
        surf_label = np.where(was_reflected[surface], Label.BEHIND_REFLECTIVE,
                              np.where(kind[surface] == 2, Label.TRANSPARENT_SURFACE, Label.REFLECTIVE_SURFACE))
        surf_obj = np.where(was_reflected[surface], reflector[surface], obj[surface])
        surf_code = np.select([kind[surface] == 1, kind[surface] == 2], [SURFACE_MIRROR, SURFACE_GLASS],
                              SURFACE_METAL)
        out.append(Returns(beam[surface], path[surface], hit[surface], surface_intensity,
                           surf_label.astype(np.uint8), surf_obj.astype(np.int32), k[surface].astype(np.int32),
                           surf_code.astype(np.uint8)))

        # Continuing rays: reflections, transmissions (glass).
        refl = reflected & (bounces < params.max_bounces)
        trans = kind == 2
        r_dir = d[refl] - 2 * cos_signed[refl, None] * sa.normal[k[refl]]
        new = [
            (refl, hit[refl], r_dir, reflect_energy[refl],
             np.where(reflector[refl] >= 0, reflector[refl], obj[refl]), pane[refl], bounces[refl] + 1),
            (trans, hit[trans], d[trans], transmit_energy[trans],
             reflector[trans], np.where(pane[trans] >= 0, pane[trans], obj[trans]), bounces[trans]),
        ]
        if not params.ideal_model:
            # Drop rays along which not even a white wall could return a detectable echo.
            new = [_worth_following(x, path, params.intensity_gain, threshold) for x in new]
        beam = np.concatenate([beam[m] for m, *_ in new])
        weight = np.concatenate([weight[m] for m, *_ in new])
        exclude = np.concatenate([k[m] for m, *_ in new])
        travelled = np.concatenate([path[m] for m, *_ in new])
        o = np.concatenate([x[1] for x in new])
        d = np.concatenate([x[2] for x in new])
        energy = np.concatenate([x[3] for x in new])
        reflector = np.concatenate([x[4] for x in new]).astype(np.int32)
        pane = np.concatenate([x[5] for x in new]).astype(np.int32)
        bounces = np.concatenate([x[6] for x in new]).astype(np.int32)

    result = Returns.concatenate(out)
    if params.ideal_model:
        return result.select(result.intensity >= params.min_intensity)
    return result


def _worth_following(continuing, path, gain, threshold):
    mask, origins, dirs, energy, reflector, pane, bounces = continuing
    ok = gain * energy ** 2 / np.maximum(path[mask], 1.0) ** 2 >= threshold
    mask = mask.copy()
    mask[np.flatnonzero(mask)[~ok]] = False
    return (mask, origins[ok], dirs[ok], energy[ok], reflector[ok], pane[ok], bounces[ok])


def _ideal_response(sa, k, kind, front, cos_inc, incidence, falloff, energy):
    """Per hit: diffuse intensity (NaN: none), surface-echo mask and intensities, reflected mask and the
    energies of the reflected and transmitted rays (module doc, ideal model)."""
    mirror_front = ((kind == 1) | (kind == 3)) & front
    diffuse = (kind == 0) | (((kind == 1) | (kind == 3)) & ~front)
    glass = kind == 2
    diffuse_intensity = np.where(diffuse, sa.albedo[k] * cos_inc * falloff * energy, np.nan)
    surface = (mirror_front | glass) & (cos_inc >= sa.cos_limit[k])
    width = np.maximum(sa.limit[k[surface]] / 2, 1e-6)
    surface_intensity = (sa.strength[k[surface]] * np.exp(-0.5 * (incidence[surface] / width) ** 2)
                         * falloff[surface] * energy[surface])
    reflected = mirror_front | (glass & (sa.reflectance[k] > 0))
    return (diffuse_intensity, surface, surface_intensity, reflected, energy * sa.reflectance[k],
            energy * sa.transmission[k])


def _realistic_response(sa, k, kind, front, cos_inc, incidence, falloff, energy):
    """As _ideal_response, for the realistic model (module doc): intensities go with energy^2."""
    specular_front = ((kind == 1) | (kind == 3)) & front
    glass = kind == 2
    diffuse = (kind == 0) | (((kind == 1) | (kind == 3)) & ~front)
    two_way = falloff * energy ** 2
    reflectance = np.where(glass, pane_reflectance(cos_inc, sa.refractive_index[k]),
                           np.where(specular_front, sa.reflectance[k], 0.0))
    diffuse_intensity = np.where(diffuse, sa.albedo[k] * cos_inc * two_way, np.nan)
    surface = specular_front | glass
    ks = k[surface]
    surface_intensity = two_way[surface] * (sa.haze[ks] * cos_inc[surface]
                                            + reflectance[surface] * specular_lobe(incidence[surface], sa.lobe[ks]))
    return (diffuse_intensity, surface, surface_intensity, surface, energy * reflectance,
            energy * (1.0 - reflectance))
