"""GeoParquet with native (GeoArrow) geometry encodings is read like WKB GeoParquet.

GeoParquet 1.1 lets a file store its geometry as nested lists of coordinates
(``geopandas.to_parquet(geometry_encoding="geoarrow")``, GDAL's
``GEOMETRY_ENCODING=GEOARROW``). The oracle is the same layer stored as WKB:
``optri batch`` must give the same records from both, with the parent reading
(one process) and with the workers reading their own row groups.
"""

from __future__ import annotations

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")  # polygons with holes

from optri import config  # noqa: E402
from optri.batch import iter_records, strip_timing  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.geo import wkb_geometry  # noqa: E402
from optri.errors import BatchInputError  # noqa: E402

HOLED = shapely.Polygon(shapely.box(50, 0, 60, 10).exterior, [shapely.box(52, 2, 54, 4).exterior])
L_SHAPE = shapely.Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 2), (0, 2)])
BOWTIE = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])


def _layer(geoms, z=False):
    return gpd.GeoDataFrame(
        {"name": [f"f{k}" for k in range(len(geoms))], "k": np.arange(len(geoms))},
        geometry=geoms,
        crs="EPSG:32633",
    )


def _records(out):
    return [strip_timing(r) for r in iter_records(out)]


LAYERS = {
    "polygon": [shapely.box(0, 0, 20, 10), HOLED, None, L_SHAPE, BOWTIE, shapely.box(5, 5, 6, 7)],
    "multipolygon": [
        shapely.MultiPolygon([shapely.box(40, 0, 41, 1), shapely.box(43, 0, 45, 2)]),
        shapely.MultiPolygon([HOLED]),
        None,
        shapely.MultiPolygon([L_SHAPE]),
    ],
    "z": [
        shapely.Polygon([(30, 0, 1), (34, 0, 2), (34, 3, 3), (30, 3, 4)]),
        None,
        shapely.Polygon([(0, 0, 0), (4, 0, 1), (4, 4, 2), (0, 4, 1)]),
    ],
}


@pytest.mark.parametrize("kind", sorted(LAYERS))
@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("reader", ["workers", "parent"])
def test_native_encoding_gives_the_records_of_wkb(tmp_path, monkeypatch, kind, workers, reader):
    monkeypatch.setattr(config, "BATCH_WORKERS_READ", reader == "workers")
    gdf = _layer(LAYERS[kind])
    wkb, native = tmp_path / "wkb.parquet", tmp_path / "native.parquet"
    gdf.to_parquet(wkb, row_group_size=2)
    gdf.to_parquet(native, geometry_encoding="geoarrow", row_group_size=2)
    schema = pq.read_schema(native)
    assert not pa.types.is_binary(schema.field("geometry").type)  # really stored natively
    expected = batch(wkb, tmp_path / "a.parquet", workers=workers, chunk_size=2)
    got = batch(native, tmp_path / "b.parquet", workers=workers, chunk_size=2)
    assert (got.ok, got.errors) == (expected.ok, expected.errors) and got.ok > 0
    assert _records(tmp_path / "b.parquet") == _records(tmp_path / "a.parquet")
    back = gpd.read_parquet(tmp_path / "b.parquet")
    assert back.crs == gdf.crs and list(back["name"]) == list(gdf["name"])
    assert shapely.is_valid(back.geometry.values[back["status"] == "ok"]).all()


def _geoarrow(geoms, kind, interleaved, dims):
    """A GeoArrow array of ``geoms`` (nulls allowed) built from shapely's ragged arrays."""
    present = np.array([g is not None for g in geoms])
    filled = np.array([g if g is not None else shapely.from_wkt(f"{kind} EMPTY") for g in geoms])
    _, coords, offsets = shapely.to_ragged_array(filled, include_z=dims == 3)
    if interleaved:
        names = "xyz"[:dims]
        values = pa.FixedSizeListArray.from_arrays(
            pa.array(coords.ravel()), type=pa.list_(pa.field(names, pa.float64()), dims)
        )
    else:
        values = pa.StructArray.from_arrays(
            [pa.array(coords[:, i]) for i in range(dims)], names=list("xyz"[:dims])
        )
    arr = values
    for level, off in enumerate(offsets):  # innermost first
        outermost = level == len(offsets) - 1
        mask = pa.array(~present) if outermost else None
        arr = pa.ListArray.from_arrays(pa.array(off.astype(np.int32)), arr, mask=mask)
    if not offsets:  # points: a struct or fixed-size list per row
        arr = pa.array(values.to_pylist(), values.type, mask=~present)
    return arr


@pytest.mark.parametrize("interleaved", [False, True])
@pytest.mark.parametrize("dims", [2, 3])
@pytest.mark.parametrize(
    "kind, geoms",
    [
        ("POLYGON", [HOLED, None, L_SHAPE, shapely.box(0, 0, 1, 1)]),
        (
            "MULTIPOLYGON",
            [
                shapely.MultiPolygon([HOLED, shapely.box(70, 0, 71, 1)]),
                None,
                shapely.MultiPolygon([L_SHAPE]),
            ],
        ),
        ("LINESTRING", [shapely.LineString([(0, 0), (1, 1)]), None]),
        ("POINT", [shapely.Point(1, 2), None, shapely.Point(3, 4)]),
    ],
)
def test_wkb_geometry_equals_the_geometries(kind, geoms, interleaved, dims):
    if dims == 3:
        geoms = [None if g is None else shapely.force_3d(g, 7.5) for g in geoms]
    arr = _geoarrow(geoms, kind, interleaved, dims)
    table = pa.table({"k": np.arange(len(geoms)), "geometry": arr})
    batch_slice = table.to_batches()[0].slice(1)  # a slice: offsets that do not start at 0
    assert batch_slice.column(1).offset == 1
    for sliced in (table, table.slice(1), batch_slice):
        out = wkb_geometry(sliced, "geometry", kind.lower())
        assert out.column("k").to_pylist() == sliced.column("k").to_pylist()
        back = [
            None if w is None else shapely.from_wkb(w) for w in out.column("geometry").to_pylist()
        ]
        want = geoms[len(geoms) - sliced.num_rows :]
        assert [b is None for b in back] == [g is None for g in want]
        for b, g in zip(back, want):
            if g is not None:
                assert shapely.equals_exact(b, g, tolerance=0) and shapely.has_z(b) == (dims == 3)


def test_wkb_is_returned_as_is_and_garbage_is_a_clear_error(tmp_path):
    table = pa.table({"geometry": pa.array([shapely.to_wkb(HOLED)])})
    assert wkb_geometry(table, "geometry", "WKB") is table
    with pytest.raises(BatchInputError, match="not 'polygon' GeoArrow data"):
        wkb_geometry(pa.table({"geometry": pa.array([1.0, 2.0])}), "geometry", "polygon")
