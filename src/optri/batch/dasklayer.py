"""Layers on a Dask cluster: workers read partitions, solve them and write GeoParquet parts.

:func:`dask_layer` is what ``optri batch --scheduler dask`` runs for GeoParquet,
GeoPackage, FlatGeobuf and shapefile inputs written as GeoParquet: each task
reads one partition of the input (``dask_geopandas.read_parquet``, or
``read_file`` through pyogrio), solves it (:func:`optri.triangulate_many` on a
dask GeoDataFrame, :mod:`.daskframe`) and writes it as one GeoParquet file; the
parent only plans the graph and, at the end, publishes the output.

Every row is written exactly once, even when a worker dies and Dask reruns its
tasks elsewhere: a part is written under a temporary name and renamed to
``part.NNNNN.parquet`` (its partition number) only once complete, so a rerun
replaces a part, never adds a second one, and half-written files never carry a
part's name. The parts are made in a hidden folder beside the output
(``.OUT.dask-parts``); only when every partition is done is that folder renamed
to the output directory, or its parts joined into the output file, so the
output never exists half made.
"""

from __future__ import annotations

import contextlib
import functools
import json
import os
import shutil
import time
import uuid
from pathlib import Path
from typing import Any

from .._optional import import_optional
from ..errors import BatchInputError
from .daskframe import triangulate_dask
from .layout import output_lock, plan_layout
from .many import triangulate_many
from .readers import detect_input_format
from .runner import dask_client
from .solver import check_options
from .summary import BatchSummary

__all__ = ["DASK_INPUTS", "dask_layer", "wants_dask_layer"]

#: Input formats whose partitions Dask workers read themselves (GeoParquet through
#: pyarrow, the others through pyogrio); JSON inputs keep the streaming reader,
#: which turns a bad feature into an error row instead of failing the read.
DASK_INPUTS = ("parquet", "gpkg", "fgb", "shp")
#: Default Dask scheduler retries of a task whose worker died, for clusters made here.
ALLOWED_FAILURES = 3
#: Rows per partition read from a GeoPackage, FlatGeobuf or shapefile by default.
DEFAULT_CHUNKSIZE = 50_000
_PART = "part.{:05d}.parquet"
_SUCCESS = "_SUCCESS"


def wants_dask_layer(
    scheduler: Any,
    inp: str | os.PathLike[str],
    out: str | os.PathLike[str],
    fmt: str | None,
    out_fmt: str | None,
) -> bool:
    """Whether ``optri.batch`` hands this run to :func:`dask_layer`.

    True for a Dask scheduler (``"dask"``, an address, or a ``distributed.Client``),
    an input Dask reads by partitions (:data:`DASK_INPUTS`) and a GeoParquet output
    (a ``.parquet`` file, or a directory with ``out_fmt="parquet"``).

    >>> wants_dask_layer("dask", "roofs.gpkg", "out.parquet", None, None)
    True
    >>> wants_dask_layer("local", "roofs.gpkg", "out.parquet", None, None)
    False
    >>> wants_dask_layer("dask", "roofs.ndjson", "out.parquet", None, None)
    False
    """
    if scheduler is None or scheduler in ("local", "processes"):
        return False
    try:
        kind = detect_input_format(inp, fmt)
        layout = plan_layout(out, out_fmt)
    except BatchInputError:
        return False  # the ordinary path reports it
    return kind in DASK_INPUTS and layout.fmt == "parquet"


def dask_layer(
    inp: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    project: bool = False,
    scheduler: Any = None,
    workers: int | None = None,
    npartitions: int | None = None,
    chunksize: int | None = None,
    layer: str | None = None,
    fmt: str | None = None,
    overwrite: bool = False,
    progress: Any = None,
    explode: bool = False,
) -> BatchSummary:
    """Triangulate a layer on a Dask cluster: workers read, solve and write GeoParquet parts.

    Parameters
    ----------
    inp : path
        GeoParquet (a file or a directory of files), GeoPackage, FlatGeobuf or
        shapefile; every worker must see it at the same path (shared storage).
    out : path
        A ``.parquet`` file, or a directory (a path ending in ``/`` or without a
        suffix) that receives ``part.00000.parquet``, ... and ``_SUCCESS``: a
        GeoParquet dataset ``geopandas.read_parquet`` and
        ``dask_geopandas.read_parquet`` open. Workers write into a hidden folder
        beside it, so it too must be on shared storage.
    weight, objective, method, project
        As for :func:`optri.triangulate_many`.
    scheduler : {None, "dask", "tcp://host:port", "dask://host:port"} or distributed.Client
        ``None`` or ``"dask"``: a LocalCluster of ``workers`` processes made for
        the run (Dask reruns a task whose worker died up to
        :data:`ALLOWED_FAILURES` times); an address: that cluster; a client: its cluster.
    workers : int, optional
        Processes of the LocalCluster (default: every core).
    npartitions, chunksize : int, optional
        Partitions of the input (``chunksize``: rows per partition). GeoParquet
        is read one row group per partition unless ``npartitions`` asks for
        another count; other formats default to :data:`DEFAULT_CHUNKSIZE` rows.
    layer : str, optional
        The layer of a GeoPackage holding several.
    fmt : str, optional
        The input format, overriding the suffix.
    overwrite : bool
        Replace an existing output (otherwise an existing output is an error).
    progress : callable, optional
        ``progress(done, total)``, called once the run is complete.
    explode : bool
        One row per triangle (:func:`optri.triangulate_many` with ``explode=True``);
        the summary still counts features.

    Returns
    -------
    BatchSummary

    Raises
    ------
    BatchInputError
        A format Dask does not read here, a missing input, an existing output
        without ``overwrite``, an output that is the input, an unknown scheduler.
    BatchLockedError
        Another run is writing the same output.

    Examples
    --------
    >>> import geopandas, shapely, tempfile, pathlib
    >>> from optri.batch import dask_layer
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> geopandas.GeoDataFrame(
    ...     {"name": ["a", "b"]}, geometry=[shapely.box(0, 0, 1, 1), shapely.box(0, 0, 2, 1)],
    ...     crs=32633).to_parquet(d / "in.parquet")
    >>> s = dask_layer(d / "in.parquet", d / "out.parquet", workers=1)  # doctest: +SKIP
    >>> geopandas.read_parquet(d / "out.parquet")["status"].tolist()  # doctest: +SKIP
    ['ok', 'ok']
    """
    start = time.perf_counter()
    src = Path(inp)
    kind = detect_input_format(src, fmt)
    if kind not in DASK_INPUTS:
        raise BatchInputError(
            f"{src}: Dask reads {', '.join(DASK_INPUTS)} inputs by partitions, not {kind}; "
            "use the local scheduler or convert the layer to GeoParquet"
        )
    if not src.exists():
        raise BatchInputError(f"{src}: no such file")
    layout = plan_layout(out, "parquet")
    layout.check_paths(src)
    target = layout.target
    options = check_options(weight, objective, method)
    with output_lock(layout.lock, target):
        if target.exists() and not overwrite:
            raise BatchInputError(f"{target} exists; pass --overwrite to replace it")
        staging = target.parent / f".{target.name}.dask-parts"
        shutil.rmtree(staging, ignore_errors=True)  # a crashed run's parts: not vouched for
        staging.mkdir(parents=True)
        try:
            ddf = _read(src, kind, npartitions, chunksize, layer)
            solve = functools.partial(triangulate_many, explode=explode)
            solved = triangulate_dask(ddf, solve, options, project)
            written = solved.map_partitions(
                write_partition, str(staging), explode, partition_info=True, meta=_counts_meta()
            )
            with dask_client(scheduler, workers, ALLOWED_FAILURES) as client:
                counts = client.compute(written).result()
            _publish(staging, target, counts, layout.single)
        finally:
            shutil.rmtree(staging, ignore_errors=True)
    total, ok = int(counts["rows"].sum()), int(counts["ok"].sum())
    if progress is not None:
        progress(total, total)
    return BatchSummary(total, ok, total - ok, len(counts), 0, time.perf_counter() - start, target)


def _counts_meta() -> Any:
    pd = import_optional("pandas", "geo")
    return pd.DataFrame(
        {
            "part": pd.Series(dtype="int64"),
            "rows": pd.Series(dtype="int64"),
            "ok": pd.Series(dtype="int64"),
        }
    )


def _read(
    src: Path, kind: str, npartitions: int | None, chunksize: int | None, layer: str | None
) -> Any:
    """The input as a dask GeoDataFrame whose partitions the workers read themselves."""
    dg = import_optional("dask_geopandas", "dask")
    if kind == "parquet":
        ddf = dg.read_parquet(str(src), split_row_groups=True)
        if chunksize is not None and npartitions is None:
            pq = import_optional("pyarrow.parquet", "geo")
            rows = sum(pq.ParquetFile(f).metadata.num_rows for f in _parquet_files(src))
            npartitions = max(1, -(-rows // chunksize))
        if npartitions is not None and npartitions != ddf.npartitions:
            ddf = ddf.repartition(npartitions=npartitions)
        return ddf
    if npartitions is None and chunksize is None:
        chunksize = DEFAULT_CHUNKSIZE
    extra = {"layer": layer} if layer is not None else {}
    try:
        return dg.read_file(str(src), npartitions=npartitions, chunksize=chunksize, **extra)
    except Exception as exc:  # pyogrio's DataSourceError, a missing layer, ...
        raise BatchInputError(f"{src}: cannot read it as a {kind} layer ({exc})") from None


def _parquet_files(src: Path) -> list[Path]:
    return sorted(src.rglob("*.parquet")) if src.is_dir() else [src]


def write_partition(
    part: Any, folder: str, explode: bool = False, partition_info: dict | None = None
) -> Any:
    """Write one solved partition as ``part.NNNNN.parquet`` in ``folder``, atomically.

    The file is written under a temporary name, flushed to disk and renamed, so
    the part's name only ever holds a complete part, and a task Dask reruns
    (its worker died) replaces the part instead of adding rows. Returns one row
    of counts (partition number, features, ok features) for the parent; the
    rows of an ``explode``-d feature share its index, one after another.
    """
    pd = import_optional("pandas", "geo")
    number = 0 if partition_info is None else int(partition_info["number"])
    final = Path(folder) / _PART.format(number)
    temp = final.with_name(f".{final.name}.{uuid.uuid4().hex}.tmp")
    try:
        part.to_parquet(temp, index=False)
        _fsync(temp)
        os.replace(temp, final)
    finally:
        with contextlib.suppress(FileNotFoundError):
            temp.unlink()
    first = part.index.to_series() != part.index.to_series().shift() if explode else None
    features = part if first is None else part[first.to_numpy()]
    ok = int((features["status"] == "ok").sum())
    return pd.DataFrame({"part": [number], "rows": [len(features)], "ok": [ok]})


def _fsync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _publish(staging: Path, target: Path, counts: Any, single: bool) -> None:
    """Make the output appear whole: every part there, once, with one schema."""
    parts = [staging / _PART.format(int(k)) for k in sorted(counts["part"])]
    missing = [p.name for p in parts if not p.is_file()]
    if missing or len(set(counts["part"])) != len(counts):
        raise BatchInputError(f"{target}: parts missing or repeated after the run: {missing}")
    for stray in staging.glob(".*.tmp"):  # left by a worker that died while writing
        stray.unlink()
    schema = _unified_schema(parts)
    if single:
        _join(parts, schema, staging / ".joined.tmp")
        os.replace(staging / ".joined.tmp", target)
        return
    for p in parts:
        _conform_part(p, schema)
    summary = {
        "rows": int(counts["rows"].sum()),
        "ok": int(counts["ok"].sum()),
        "partitions": len(parts),
    }
    (staging / _SUCCESS).write_text(json.dumps(summary) + "\n")
    if target.exists():
        shutil.rmtree(target)
    os.rename(staging, target)


def _unified_schema(parts: list[Path]) -> Any:
    """One Arrow schema for all parts (a column null in one part takes the others' type)."""
    pa = import_optional("pyarrow", "geo")
    pq = import_optional("pyarrow.parquet", "geo")
    schemas = [pq.read_schema(p) for p in parts]
    unified = pa.unify_schemas(schemas, promote_options="permissive")
    return unified.with_metadata(_geo_metadata(schemas))


def _geo_metadata(schemas: list[Any]) -> dict:
    """The first part's metadata, with the bounding box and geometry types of all parts."""
    meta = dict(schemas[0].metadata or {})
    geo = [json.loads(s.metadata[b"geo"]) for s in schemas if s.metadata and b"geo" in s.metadata]
    if not geo:
        return meta
    merged = geo[0]
    for name, column in merged.get("columns", {}).items():
        others = [g["columns"].get(name, {}) for g in geo]
        column["geometry_types"] = sorted({t for o in others for t in o.get("geometry_types", [])})
        boxes = [o["bbox"] for o in others if o.get("bbox")]
        if boxes:
            column["bbox"] = [
                min(b[0] for b in boxes),
                min(b[1] for b in boxes),
                max(b[2] for b in boxes),
                max(b[3] for b in boxes),
            ]
        else:
            column.pop("bbox", None)
    meta[b"geo"] = json.dumps(merged).encode()
    return meta


def _join(parts: list[Path], schema: Any, dest: Path) -> None:
    """Stream every part, in partition order, into one GeoParquet file."""
    pq = import_optional("pyarrow.parquet", "geo")
    with pq.ParquetWriter(dest, schema) as writer:
        for p in parts:
            table = pq.read_table(p)
            if table.num_rows:
                writer.write_table(table.cast(schema))
    _fsync(dest)


def _conform_part(path: Path, schema: Any) -> None:
    """Rewrite a part whose column types differ from the dataset's (all-null columns)."""
    pq = import_optional("pyarrow.parquet", "geo")
    if pq.read_schema(path).remove_metadata().equals(schema.remove_metadata()):
        return
    temp = path.with_name(f".{path.name}.cast.tmp")
    pq.write_table(pq.read_table(path).cast(schema), temp)
    os.replace(temp, path)
