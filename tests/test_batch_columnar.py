"""Arrow layers into table outputs are solved as columns, with the records of the feature path."""

from __future__ import annotations

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyogrio = pytest.importorskip("pyogrio")
shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")

from batch_polys import killer, write_arrow_layer  # noqa: E402
from optri import config  # noqa: E402
from optri.batch import chunks, iter_records, partwork, runner, strip_timing  # noqa: E402
from optri.batch.driver import batch  # noqa: E402

HEPT = shapely.Polygon([(np.cos(a), np.sin(a)) for a in np.linspace(0, 6, 7)])
GEOMS = [
    shapely.box(0, 0, 20, 10),
    shapely.Polygon([(30, 0, 1), (34, 0, 2), (34, 3, 3), (30, 3, 4)]),
    shapely.MultiPolygon([shapely.box(40, 0, 41, 1), shapely.box(43, 0, 45, 2)]),
    shapely.Polygon(shapely.box(50, 0, 60, 10).exterior, [shapely.box(52, 2, 54, 4).exterior]),
    None,
    shapely.Polygon(),
    shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]),  # a bow-tie
    shapely.Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 2), (0, 2)]),
    shapely.Point(1, 2),
]


def _write(path, ids=None):
    cols = {"name": [f"f{k}" for k in range(len(GEOMS))]}
    if ids is not None:
        cols["id"] = ids
    cols["geometry"] = pa.array(shapely.to_wkb(np.array(GEOMS, object)), pa.binary())
    return write_arrow_layer(path, pa.table(cols))


def _records(out):
    return [strip_timing(r) for r in iter_records(out)]


@pytest.mark.parametrize("source", [".parquet", ".gpkg"])
@pytest.mark.parametrize("ids", [None, [f"b{k}" for k in range(9)], [7, None, *range(9, 16)]])
@pytest.mark.parametrize("out", ["o.parquet", "o.gpkg", "o.fgb", "parts/"])
def test_columns_give_the_feature_paths_records(tmp_path, monkeypatch, source, ids, out):
    src = _write(tmp_path / f"in{source}", ids)
    calls = []
    real = chunks.solve_table
    monkeypatch.setattr(chunks, "solve_table", lambda t: (calls.append(t), real(t))[1])
    monkeypatch.setattr(runner, "solve_table", chunks.solve_table)
    monkeypatch.setattr(partwork, "solve_table", chunks.solve_table)  # the worker reads too
    fmt = "parquet" if out.endswith("/") else None  # a directory of Parquet parts
    batch(src, str(tmp_path / "a" / out), workers=1, chunk_size=4, out_fmt=fmt)
    assert len(calls) == 3  # nine rows, chunks of four: solved as tables
    monkeypatch.setattr(config, "BATCH_COLUMNAR", False)
    batch(src, str(tmp_path / "b" / out), workers=1, chunk_size=4, out_fmt=fmt)
    assert len(calls) == 3
    assert _records(tmp_path / "a" / out) == _records(tmp_path / "b" / out)


def test_weight_objective_and_lexicographic_costs_agree(tmp_path, monkeypatch):
    src = _write(tmp_path / "in.parquet")
    for weight, objective in (("area", "max"), (("max_angle", "perimeter"), ("max", "sum"))):
        opts = dict(workers=1, weight=weight, objective=objective, overwrite=True)
        batch(src, tmp_path / "a.parquet", **opts)
        monkeypatch.setattr(config, "BATCH_COLUMNAR", False)
        batch(src, tmp_path / "b.parquet", **opts)
        monkeypatch.setattr(config, "BATCH_COLUMNAR", True)
        assert _records(tmp_path / "a.parquet") == _records(tmp_path / "b.parquet")


def test_a_killed_worker_fails_its_row_only(tmp_path):
    table = pa.table(
        {
            "k": list(range(6)),
            "geometry": pa.array(
                [shapely.to_wkb(HEPT if i == 3 else shapely.box(i, 0, i + 1, 1)) for i in range(6)],
                pa.binary(),
            ),
        }
    )
    src = tmp_path / "in.parquet"
    pq.write_table(table, src)
    s = batch(src, tmp_path / "out.parquet", weight=killer, workers=2, chunk_size=2)
    recs = list(iter_records(tmp_path / "out.parquet"))
    assert (s.ok, s.errors) == (5, 1)
    assert [r["k"] for r in recs] == list(range(6))
    assert "worker process died" in recs[3]["reason"] and "3" in recs[3]["reason"]
