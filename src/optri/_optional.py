"""Import optional dependencies lazily, with an error that names the extra."""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import EngineUnavailableError

__all__ = ["import_optional"]

#: module name -> extra that installs it
_EXTRAS = {
    "matplotlib": "plot",
    "trimesh": "mesh",
    "shapely": "shapely",
    "numba": "fast",
    "numba.cuda": "gpu",
    "scipy": "mesh",
    "dask": "dask",
    "distributed": "dask",
    "geopandas": "geo",
    "pyogrio": "geo",
    "pyarrow": "geo",
    "mapbox_earcut": "compare",
}


def import_optional(name: str) -> ModuleType:
    """Import module ``name`` or raise :class:`EngineUnavailableError`.

    The message names the ``pip install optri[extra]`` that brings it.
    """
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        extra = _EXTRAS.get(name, _EXTRAS.get(name.split(".")[0], ""))
        hint = f"; install it with: pip install 'optri[{extra}]'" if extra else ""
        raise EngineUnavailableError(f"{name} is not available ({exc}){hint}") from exc
