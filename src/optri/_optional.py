"""Import optional dependencies lazily, with an error that names the extra to install."""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import MissingDependencyError

__all__ = ["EXTRAS", "import_optional"]

#: top-level module name -> the extra of ``pyproject.toml`` that installs it
EXTRAS = {
    "trimesh": "mesh",
    "scipy": "mesh",
    "shapely": "shapely",
    "numba_cuda": "gpu",
    "numba": "numba",
    "dask": "dask",
    "distributed": "dask",
    "dask_geopandas": "dask",
    "geopandas": "geo",
    "pyogrio": "geo",
    "pyarrow": "geo",
    "pyproj": "geo",
    "mapbox_earcut": "compare",
    "pydicom": "contours",
}


def import_optional(name: str, extra: str | None = None) -> ModuleType:
    """Import module ``name`` or raise :class:`~optri.errors.MissingDependencyError`.

    The message names the ``pip install 'optri[extra]'`` that brings it (``extra``
    overrides :data:`EXTRAS` where one package serves several extras); core
    dependencies (numpy, matplotlib, click, rich) are named as packages.

    >>> import_optional("math").pi > 3
    True
    """
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        top = name.split(".")[0]
        extra = extra or EXTRAS.get("numba_cuda" if name.startswith("numba.cuda") else top)
        hint = f"pip install 'optri[{extra}]'" if extra else f"pip install {top}"
        raise MissingDependencyError(
            f"{name} is not available ({exc}); install it with: {hint}"
        ) from exc
