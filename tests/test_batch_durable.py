"""A job parses its layer's CRS once and syncs each file to the disk once, not per part."""

from __future__ import annotations

import os

import pytest

gpd = pytest.importorskip("geopandas")
pyproj = pytest.importorskip("pyproj")
shapely = pytest.importorskip("shapely")

from optri.batch import iter_records  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.layer import crs_wkt  # noqa: E402
from optri.batch.project import parsed_crs  # noqa: E402

ROWS = 12


def _layer(path, crs="EPSG:32633"):
    geoms = [shapely.box(390000 + 50 * i, 5820000, 390020 + 50 * i, 5820010) for i in range(ROWS)]
    gpd.GeoDataFrame({"k": range(ROWS)}, geometry=geoms, crs=crs).to_parquet(path)
    return path


def _clear_caches():
    parsed_crs.cache_clear()
    crs_wkt.cache_clear()


@pytest.mark.parametrize("suffix", [".parquet", ".gpkg", ".geojson", "/"])
def test_crs_parsed_once_per_job(tmp_path, monkeypatch, suffix):
    src = _layer(tmp_path / "in.parquet")
    calls = []
    real = pyproj.CRS.from_user_input

    def counting(value, *a, **k):
        calls.append(value)
        return real(value, *a, **k)

    _clear_caches()
    monkeypatch.setattr(pyproj.CRS, "from_user_input", staticmethod(counting))
    out = str(tmp_path / "out") + suffix
    fmt = {"/": "parquet"}.get(suffix)
    batch(src, out, workers=1, chunk_size=2, out_fmt=fmt)  # six parts
    assert len(calls) == 1
    assert [r["status"] for r in iter_records(out)] == ["ok"] * ROWS


def _fsyncs(monkeypatch, tmp_path, out, chunk):
    calls = []
    real = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (calls.append(fd), real(fd))[1])
    batch(_layer(tmp_path / "in.parquet"), out, workers=1, chunk_size=chunk, overwrite=True)
    monkeypatch.setattr(os, "fsync", real)
    return len(calls)


@pytest.mark.parametrize("name", ["out.parquet", "out.ndjson", "out.fgb"])
def test_single_file_syncs_do_not_grow_with_parts(tmp_path, monkeypatch, name):
    one = _fsyncs(monkeypatch, tmp_path, tmp_path / name, ROWS)
    many = _fsyncs(monkeypatch, tmp_path, tmp_path / name, 1)
    assert one == many
    assert one <= 4  # manifest, _SUCCESS, the file, its receipt


def test_directory_syncs_each_part_once(tmp_path, monkeypatch):
    one = _fsyncs(monkeypatch, tmp_path, str(tmp_path / "parts") + "/", ROWS)
    many = _fsyncs(monkeypatch, tmp_path, str(tmp_path / "parts") + "/", 1)
    assert many - one == ROWS - 1  # one more fsync per extra part, none per ledger line


def test_resume_redoes_a_part_cut_short_by_a_power_cut(tmp_path):
    """An unsynced part that lost its bytes no longer matches its hash: it is redone."""
    src = _layer(tmp_path / "in.parquet")
    out = tmp_path / "parts"
    batch(src, str(out) + "/", workers=1, chunk_size=4)
    before = [r for r in iter_records(out)]
    (out / "_SUCCESS").unlink()
    part = out / "part-00001.ndjson"
    part.write_bytes(part.read_bytes()[:10])  # what a power cut may leave of an unsynced file
    s = batch(src, str(out) + "/", workers=1, chunk_size=4)
    assert s.reused == 2
    assert [r["id"] for r in iter_records(out)] == [r["id"] for r in before]
