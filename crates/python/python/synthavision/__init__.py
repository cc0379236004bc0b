"""SynthaVision for Python: load scenes, COMGEOM decks, FLUKA, MCNP and
OpenMC inputs; render pictures as numpy arrays; cut sections; check for
overlaps; compute volumes; render films, on one machine or a Dask cluster
(``synthavision.dask``).

>>> import synthavision as sv
>>> model = sv.load("examples/helicopter/helicopter.sv")
>>> image = model.render(size=(320, 240))
>>> image.region.shape
(240, 320)
"""

from ._native import (
    Camera,
    Film,
    Image,
    Light,
    Model,
    ParseError,
    Region,
    Section,
    __version__,
    load,
)
from . import dask  # noqa: E402  (imports Dask itself only when used)

__all__ = [
    "Camera",
    "Film",
    "Image",
    "Light",
    "Model",
    "ParseError",
    "Region",
    "Section",
    "__version__",
    "dask",
    "load",
]
