"""Vectorised beam tracing through a scene of rectangles: every return a beam produces.

Beams are traced in chunks (numpy over beams x rectangles, no Python loop over
beams). A beam is a set of rays; each step intersects all live rays with all
rectangles, takes the nearest hit and applies the material:

* diffuse surface (or the back of a mirror): a return at the hit; the ray ends.
* mirror front: if the incidence angle is below the material's limit, a
  surface echo at the hit; in any case the ray is reflected (ray direction
  mirrored across the plane) and continues, up to `max_bounces` reflections
  (after that the light is considered lost: no further return).
* glass: a surface echo below the incidence limit; the ray is transmitted
  unchanged in direction (attenuated by `transmission`); with
  `reflectance` > 0 a reflected ray is split off as well.

A return's range is the total path length from the scanner, and the scanner
puts it along the *original* beam direction: a return after a reflection is a
phantom at range = path length, behind the mirror. Its true position is the
point actually hit. Returns beyond `max_range` of path length are lost.

Intensity (arbitrary units, ~Hokuyo scale): diffuse
`gain * albedo * cos(incidence) / max(range, 1 m)^2`; surface echo of a
mirror/glass `gain * strength * exp(-0.5 (incidence / (limit/2))^2) / max(range, 1 m)^2`
(peaked at perpendicular incidence); every reflection multiplies the
ray's energy by the mirror reflectance (or the glass reflectance), every
transmission by the glass transmission. Returns below `min_intensity` are not
detected (grazing, far or heavily attenuated returns).

Ground-truth label of a return: a ray that has been reflected at least once
makes `behindReflective` returns (object = the first reflecting object: its
plane is the one the phantom appears behind, and back-projecting across it
undoes a single reflection); otherwise a ray that went through glass makes
`behindTransparent` returns (object = the first pane), except surface echoes
of another mirror/glass object, which keep their own surface label; a ray that
met nothing special makes `valid` returns. Surface echoes of a ray not yet
reflected are `reflectiveSurface` / `transparentSurface` of that object.
"""
from dataclasses import dataclass

import numpy as np

from .labels import Label
from .scene import DIFFUSE, GLASS, MIRROR

_KIND_CODE = {DIFFUSE: 0, MIRROR: 1, GLASS: 2}


@dataclass(frozen=True)
class PhysicsParams:
    max_bounces: int = 4          # reflections after which a ray is dropped
    max_steps: int = 12           # surfaces a ray may meet (reflections + transmissions + final hit)
    intensity_gain: float = 8000.0
    min_intensity: float = 0.5
    chunk_beams: int = 16384      # beams per vectorised chunk (memory ~ chunk x rectangles)


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
        self.object_id = np.array([r.object_id for r in rects], np.int32)
        m = [r.material for r in rects]
        self.kind = np.array([_KIND_CODE[x.kind] for x in m], np.int8)
        self.albedo = np.array([x.albedo for x in m], float)
        self.cos_limit = np.cos(np.radians([x.surface_echo_max_incidence_deg for x in m])).reshape(-1)
        self.limit = np.radians([x.surface_echo_max_incidence_deg for x in m]).reshape(-1)
        self.strength = np.array([x.surface_echo_strength for x in m], float)
        self.reflectance = np.array([x.reflectance for x in m], float)
        self.transmission = np.array([x.transmission for x in m], float)
        self.cn = np.einsum('ij,ij->i', self.centre, self.normal)
        self.cu = np.einsum('ij,ij->i', self.centre, self.u)
        self.cv = np.einsum('ij,ij->i', self.centre, self.v)

    def nearest_hit(self, origins, directions, exclude):
        """Distance and index of the nearest rectangle hit by each ray (inf, -1 if none).

        exclude: per ray a rectangle index to ignore (the one the ray leaves), or -1.
        The rays x rectangles test runs in float32 with in-place operations (it is
        memory bound); the distance to the chosen rectangle is then recomputed in float64.
        """
        n_rays = len(origins)
        if n_rays == 0 or len(self.cn) == 0:
            return np.full(n_rays, np.inf), np.full(n_rays, -1)
        f32 = np.float32
        o32, d32 = origins.astype(f32), directions.astype(f32)
        normal, u, v = self.normal.T.astype(f32), self.u.T.astype(f32), self.v.T.astype(f32)
        with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
            denom = d32 @ normal
            t = o32 @ normal
            np.subtract(self.cn.astype(f32), t, out=t)
            np.divide(t, denom, out=t)
            ok = t > 1e-6
            for axis, centre_dot, half in ((u, self.cu, self.half_w), (v, self.cv, self.half_h)):
                a = d32 @ axis
                a *= t
                a += o32 @ axis
                a -= centre_dot.astype(f32)
                np.abs(a, out=a)
                ok &= a <= (half + 1e-5).astype(f32)
        rows = np.nonzero(exclude >= 0)[0]
        ok[rows, exclude[rows]] = False
        np.copyto(t, f32(np.inf), where=~ok)
        k = np.argmin(t, axis=1)
        hit = np.isfinite(t[np.arange(n_rays), k])
        k = np.where(hit, k, -1)
        nk = self.normal[np.maximum(k, 0)]
        with np.errstate(divide='ignore', invalid='ignore'):
            t_exact = (self.cn[np.maximum(k, 0)] - np.einsum('ij,ij->i', origins, nk)) / \
                np.einsum('ij,ij->i', directions, nk)
        return np.where(hit, t_exact, np.inf), k


@dataclass
class Returns:
    """All returns of a set of beams (unordered): one entry per return."""
    beam: np.ndarray        # int64, index of the beam
    path_length: np.ndarray  # float64, total path length = range the scanner measures (before noise)
    true_world: np.ndarray  # (n, 3) float64, the point actually hit, world frame
    intensity: np.ndarray   # float64
    label: np.ndarray       # uint8 Label
    object_id: np.ndarray   # int32, -1 none

    @staticmethod
    def empty():
        return Returns(np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.uint8),
                       np.zeros(0, np.int32))

    @staticmethod
    def concatenate(parts):
        parts = [Returns.empty()] + list(parts)
        return Returns(*(np.concatenate([getattr(p, f) for p in parts])
                         for f in ('beam', 'path_length', 'true_world', 'intensity', 'label', 'object_id')))


def trace(scene_arrays, origin, directions, max_range, params=PhysicsParams(), beam_offset=0):
    """Traces beams from one origin (3,) along unit directions (n, 3) in the world frame.

    Returns every return of every beam (Returns); beam indices are
    beam_offset + row index of `directions`.
    """
    parts = []
    for start in range(0, len(directions), params.chunk_beams):
        d = directions[start:start + params.chunk_beams]
        parts.append(_trace_chunk(scene_arrays, np.asarray(origin, float), d, max_range, params,
                                  beam_offset + start))
    return Returns.concatenate(parts)


def _trace_chunk(sa, origin, directions, max_range, params, beam_offset):
    n = len(directions)
    beam = np.arange(n) + beam_offset
    o = np.broadcast_to(origin, (n, 3)).copy()
    d = directions.astype(float)
    travelled = np.zeros(n)
    energy = np.ones(n)
    reflector = np.full(n, -1, np.int32)   # object id of the first reflecting object
    pane = np.full(n, -1, np.int32)        # object id of the first glass passed
    bounces = np.zeros(n, np.int32)
    exclude = np.full(n, -1)
    out = []
    gain = params.intensity_gain

    for _ in range(params.max_steps):
        if len(beam) == 0:
            break
        t, k = sa.nearest_hit(o, d, exclude)
        alive = (k >= 0) & (travelled + t <= max_range)
        beam, o, d, t, k = beam[alive], o[alive], d[alive], t[alive], k[alive]
        travelled, energy, reflector, pane, bounces = (travelled[alive], energy[alive], reflector[alive],
                                                       pane[alive], bounces[alive])
        if len(beam) == 0:
            break
        hit = o + t[:, None] * d
        path = travelled + t
        cos_signed = np.einsum('ij,ij->i', d, sa.normal[k])     # < 0: hit from the front side
        cos_inc = np.abs(cos_signed)
        incidence = np.arccos(np.clip(cos_inc, 0.0, 1.0))
        falloff = 1.0 / np.maximum(path, 1.0) ** 2
        kind = sa.kind[k]
        obj = sa.object_id[k]
        mirror_front = (kind == 1) & (cos_signed < 0)
        diffuse = (kind == 0) | ((kind == 1) & ~mirror_front)
        glass = kind == 2
        was_reflected = reflector >= 0
        in_behind_label = np.where(was_reflected, Label.BEHIND_REFLECTIVE,
                                   np.where(pane >= 0, Label.BEHIND_TRANSPARENT, Label.VALID)).astype(np.uint8)
        in_behind_obj = np.where(was_reflected, reflector, np.where(pane >= 0, pane, -1)).astype(np.int32)

        # Diffuse returns end the ray.
        sel = diffuse
        out.append(Returns(beam[sel], path[sel], hit[sel],
                           gain * sa.albedo[k[sel]] * cos_inc[sel] * falloff[sel] * energy[sel],
                           in_behind_label[sel], in_behind_obj[sel]))

        # Surface echoes of mirrors (front) and glass near perpendicular incidence.
        sel = (mirror_front | glass) & (cos_inc >= sa.cos_limit[k])
        width = np.maximum(sa.limit[k[sel]] / 2, 1e-6)
        surf_label = np.where(was_reflected[sel], Label.BEHIND_REFLECTIVE,
                              np.where(kind[sel] == 1, Label.REFLECTIVE_SURFACE, Label.TRANSPARENT_SURFACE))
        surf_obj = np.where(was_reflected[sel], reflector[sel], obj[sel])
        out.append(Returns(beam[sel], path[sel], hit[sel],
                           gain * sa.strength[k[sel]] * np.exp(-0.5 * (incidence[sel] / width) ** 2)
                           * falloff[sel] * energy[sel],
                           surf_label.astype(np.uint8), surf_obj.astype(np.int32)))

        # Continuing rays: reflections (mirror front; glass with reflectance > 0), transmissions (glass).
        refl = (mirror_front & (bounces < params.max_bounces)) | \
               (glass & (sa.reflectance[k] > 0) & (bounces < params.max_bounces))
        r_dir = d[refl] - 2 * cos_signed[refl, None] * sa.normal[k[refl]]
        trans = glass
        new = [
            (refl, hit[refl], r_dir, energy[refl] * sa.reflectance[k[refl]],
             np.where(reflector[refl] >= 0, reflector[refl], obj[refl]), pane[refl], bounces[refl] + 1),
            (trans, hit[trans], d[trans], energy[trans] * sa.transmission[k[trans]],
             reflector[trans], np.where(pane[trans] >= 0, pane[trans], obj[trans]), bounces[trans]),
        ]
        beam = np.concatenate([beam[m] for m, *_ in new])
        exclude = np.concatenate([k[m] for m, *_ in new])
        travelled = np.concatenate([path[m] for m, *_ in new])
        o = np.concatenate([x[1] for x in new])
        d = np.concatenate([x[2] for x in new])
        energy = np.concatenate([x[3] for x in new])
        reflector = np.concatenate([x[4] for x in new]).astype(np.int32)
        pane = np.concatenate([x[5] for x in new]).astype(np.int32)
        bounces = np.concatenate([x[6] for x in new]).astype(np.int32)

    result = Returns.concatenate(out)
    keep = result.intensity >= params.min_intensity
    return Returns(*(getattr(result, f)[keep] for f in
                     ('beam', 'path_length', 'true_world', 'intensity', 'label', 'object_id')))
