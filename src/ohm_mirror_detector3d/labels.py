"""Point labels, the values of the `label` field (see DESIGN.md).

The numbers follow the original implementation so old tools keep working;
they must match include/ohm_mirror_detector3d/core/labels.h.
"""
import enum


class Label(enum.IntEnum):
    UNCHECKED = 0
    VALID = 1
    ERROR_SURFACE = 2
    BEHIND_ERROR_S = 3
    REFLECTIVE_SURFACE = 4
    BEHIND_REFLECTIVE = 5
    TRANSPARENT_SURFACE = 6
    BEHIND_TRANSPARENT = 7
    NAN_POINT = 8
    ERROR = 9

    @property
    def design_name(self):
        """The name used in DESIGN.md, the paper and the C++ core (e.g. errorSurface)."""
        head, *rest = self.name.lower().split('_')
        return head + ''.join(word.capitalize() for word in rest)


# Labels whose points go to mapping (back-projected for BEHIND_REFLECTIVE).
KEPT_IN_CLEANED = frozenset({
    Label.VALID, Label.ERROR_SURFACE, Label.BEHIND_ERROR_S, Label.REFLECTIVE_SURFACE,
    Label.BEHIND_REFLECTIVE, Label.TRANSPARENT_SURFACE, Label.BEHIND_TRANSPARENT,
})

# Colours of the paper's figures (RGB, 0..1): valid green, surface turquoise, behind orange.
LABEL_COLOURS = {
    Label.UNCHECKED: (0.5, 0.5, 0.5),
    Label.VALID: (0.1, 0.7, 0.1),
    Label.ERROR_SURFACE: (0.25, 0.88, 0.82),
    Label.REFLECTIVE_SURFACE: (0.25, 0.88, 0.82),
    Label.TRANSPARENT_SURFACE: (0.25, 0.88, 0.82),
    Label.BEHIND_ERROR_S: (1.0, 0.55, 0.0),
    Label.BEHIND_REFLECTIVE: (1.0, 0.55, 0.0),
    Label.BEHIND_TRANSPARENT: (1.0, 0.55, 0.0),
    Label.NAN_POINT: (0.3, 0.3, 0.3),
    Label.ERROR: (0.8, 0.1, 0.1),
}
