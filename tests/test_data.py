"""Bundled sample data: optri.data and ``optri data``, from the package, not the repository."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

import optri
from cli_run import run_optri
from optri.cli import main
from optri.errors import OptriError, UnknownSampleError

REPO = Path(__file__).resolve().parents[1]
SAMPLES = ["footprints.ndjson", "italy.geojson", "octagon.csv", "sphere_two_holes.obj"]


def test_names_and_paths_are_the_package_files():
    assert optri.data.names() == SAMPLES
    for name in SAMPLES:
        path = optri.data.path(name)
        assert path.is_absolute() and path.is_file()
        assert path.parent == Path(optri.data.__file__).resolve().parent


def test_repository_examples_are_the_same_files():
    # examples/ keeps the paths the docs use; its sample files are the package's
    for name in SAMPLES:
        assert (REPO / "examples" / name).read_bytes() == optri.data.path(name).read_bytes()


def test_samples_solve_as_documented():
    octagon = optri.triangulate(optri.data.path("octagon.csv"), method="memo")
    assert octagon.n == 8
    octagon.check()
    italy = optri.triangulate(optri.data.path("italy.geojson"), weight="diagonal")
    assert italy.n == 65 and italy.orientation in ("ccw", "cw")
    italy.check()


def test_unknown_name_is_an_optri_error_listing_the_samples():
    with pytest.raises(UnknownSampleError, match="octagon.csv") as info:
        optri.data.path("../pyproject.toml")
    assert isinstance(info.value, OptriError) and isinstance(info.value, LookupError)


def test_copy_to_writes_every_sample(tmp_path):
    written = optri.data.copy_to(tmp_path / "new")
    assert [p.name for p in written] == SAMPLES
    for path in written:
        assert path.read_bytes() == optri.data.path(path.name).read_bytes()


def test_copy_to_writes_nothing_when_a_name_is_unknown(tmp_path):
    with pytest.raises(UnknownSampleError):
        optri.data.copy_to(tmp_path, ["octagon.csv", "nope.csv"])
    assert list(tmp_path.iterdir()) == []


def test_cli_lists_prints_and_copies(tmp_path):
    runner = CliRunner()
    listing = runner.invoke(main, ["data"])
    assert listing.exit_code == 0
    assert [line.split()[0] for line in listing.output.splitlines()] == SAMPLES
    one = runner.invoke(main, ["data", "octagon.csv"])
    assert one.exit_code == 0 and one.output.strip() == str(optri.data.path("octagon.csv"))
    copied = runner.invoke(main, ["data", "-o", str(tmp_path), "italy.geojson"])
    assert copied.exit_code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["italy.geojson"]


def test_cli_unknown_sample_is_one_line_and_exit_2(tmp_path):
    result = run_optri("data", "nope.csv", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        "optri: error: no sample file 'nope.csv'; the samples are " + ", ".join(SAMPLES)
    ]


def test_documented_commands_work_in_an_empty_folder(tmp_path):
    # the README's recipe after a plain install: copy the samples, then use examples/...
    assert run_optri("data", "-o", "examples", cwd=tmp_path).returncode == 0
    solved = run_optri("solve", "examples/octagon.csv", "--method", "memo", cwd=tmp_path)
    assert solved.returncode == 0, solved.stderr
    assert "optimal weight: 140.229243334" in solved.stdout  # the octagon of docs/paper.md
