"""hedra: exact solid modeling of polyhedral scenes, from Python.

The compiled extension ``hedra._hedra`` holds the bindings of the C++ API; this package
re-exports them and adds :class:`Image` (a numpy array that notebooks show as a PNG).
Arrays cross the boundary as copies: numpy arrays passed in are read once, arrays returned
are new (writing to them never changes a Body or a Scene). See docs/python.md.
"""

import numpy as _np

from . import _hedra
from ._hedra import (  # noqa: F401
    Body,
    Camera,
    Cancelled,
    DecompositionFailed,
    HiddenLines,
    InvalidInput,
    IoError,
    Light,
    LightList,
    Material,
    Scene,
    Shadows,
    shadows,
    SunStudy,
    box,
    clip,
    combine_sun_studies,
    cone,
    cylinder,
    decompose,
    demo_scene,
    encode_png,
    exact_volume_sign,
    frustum,
    hidden_lines,
    intersect,
    prism,
    pyramid,
    read,
    regular_prism,
    sphere,
    subtract,
    sun_study,
    sun_study_steps,
    unite,
    write,
)

__version__ = _hedra.__version__


class Image(_np.ndarray):
    """An (h, w, 3) uint8 RGB picture: a numpy array that notebooks display (``_repr_png_``)."""

    def _repr_png_(self):
        return encode_png(_np.ascontiguousarray(self, dtype=_np.uint8))

    def to_png(self):
        """The picture as PNG bytes."""
        return self._repr_png_()

    def save(self, path):
        """Writes the picture as a PNG file."""
        with open(path, "wb") as f:
            f.write(self.to_png())


def render(scene, width=0, height=0, shadows="exact", shading="phong", aa=1, lines=False,
           ambient=1.0, attenuation="none", threads=0, progress=None):
    """Shaded picture of the scene with its camera and lights: an :class:`Image`, (h, w, 3)
    uint8. ``shadows``: "exact", "map[:RES[:BIAS]]", "rays[:SPP]" or "none"; ``shading``:
    "flat", "gouraud" or "phong"; ``aa``: 1, 4 or 16 samples per pixel; ``lines``: draw the
    visible edges on top. 0 sizes take the scene camera's. ``progress(done)``, done from 0 to
    1, returning False cancels (:class:`Cancelled`)."""
    rgb = _hedra.render(scene, width, height, shadows, shading, aa, lines, ambient,
                        attenuation, threads, progress)
    return rgb.view(Image)


__all__ = [name for name in dir() if not name.startswith("_") and name != "_np"]
