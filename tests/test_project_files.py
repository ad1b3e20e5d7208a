"""Project files and packaging: licence, citation, changelog, one version, the wheel, docs.

The wheel test builds optri with ``pip wheel --no-deps --no-build-isolation`` from a
copy of the checkout and inspects it: the sample data, the licence, the metadata,
and no setuptools deprecation warning while building.
"""

from __future__ import annotations

import importlib
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import optri

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    tomllib = pytest.importorskip("tomli")

REPO = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text())
DOI = "10.7494/csci.2019.20.2.3193"
#: phrases written before a feature existed; the docs must not carry them any more
STALE = [
    "until simple polygons are supported",
    "once simple polygons are supported",
    'once `method="fast"` exists',
    "once method=fast exists",
    "What a compiled kernel must do",
]


def _makefile_recipe(target: str) -> str:
    text = (REPO / "Makefile").read_text()
    match = re.search(rf"^{target}:.*\n((?:\t.*\n|[ ].*\n)*)", text, re.M)
    assert match, f"Makefile has no {target} target"
    return match.group(0)


def test_licence_is_mit_and_declared_as_spdx():
    assert (REPO / "LICENSE").read_text().startswith("MIT License")
    project = PYPROJECT["project"]
    assert project["license"] == "MIT"
    assert project["license-files"] == ["LICENSE"]
    # a licence classifier beside an SPDX expression is refused by setuptools >= 77
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
    assert PYPROJECT["build-system"]["requires"] == ["setuptools>=77"]


def test_one_version_source():
    assert "version" not in PYPROJECT["project"]
    assert "version" in PYPROJECT["project"]["dynamic"]
    attr = PYPROJECT["tool"]["setuptools"]["dynamic"]["version"]["attr"]
    assert attr == "optri._version.__version__"
    assigned = [
        path.relative_to(REPO).as_posix()
        for path in (REPO / "src").rglob("*.py")
        if re.search(r"^__version__\s*=", path.read_text(), re.M)
    ]
    assert assigned == ["src/optri/_version.py"]
    citation = (REPO / "CITATION.cff").read_text()
    assert re.search(r"^version: (\S+)$", citation, re.M).group(1) == optri.__version__


def test_citation_names_optri_and_the_paper():
    yaml = pytest.importorskip("yaml")
    cff = yaml.safe_load((REPO / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["license"] == "MIT"
    assert cff["title"].startswith("optri")
    paper = cff["preferred-citation"]
    assert paper == cff["references"][0]
    assert paper["doi"] == DOI and paper["year"] == 2019
    assert (paper["journal"], paper["volume"], paper["issue"]) == ("Computer Science", 20, 2)
    families = [a["family-names"] for a in paper["authors"]]
    assert families == ["Selimi", "Krrabaj", "Saračević", "Pepić"]


def test_changelog_keeps_an_unreleased_section():
    text = (REPO / "CHANGELOG.md").read_text()
    assert "Keep a Changelog" in text
    assert re.search(r"^## \[Unreleased\]$", text, re.M)
    assert re.search(rf"^## \[{re.escape(optri.__version__)}\]$", text, re.M)


def test_project_metadata():
    project = PYPROJECT["project"]
    assert DOI in project["urls"]["Paper"]
    assert {"triangulation", "dynamic programming"} <= set(project["keywords"])
    assert "Typing :: Typed" in project["classifiers"]
    extras = project["optional-dependencies"]
    dev = " ".join(extras["dev"])
    assert "ruff" in dev and "mypy" in dev and "all,test,docs" in dev
    assert not [r for r in extras["test"] if r.startswith(("ruff", "mypy"))]


def test_package_data_patterns_each_match_a_file():
    package = REPO / "src" / "optri"
    patterns = PYPROJECT["tool"]["setuptools"]["package-data"]["optri"]
    for pattern in patterns:
        assert list(package.glob(pattern)), f"package-data {pattern!r} matches nothing"
    covered = {p for pattern in patterns for p in package.glob(pattern)}
    for name in optri.data.names():
        assert package / "data" / name in covered, f"{name} would not be in the wheel"


def test_demo_installs_the_base_package_and_test_builds_the_docs():
    demo = _makefile_recipe("demo")
    assert demo.startswith("demo: $(BASE)\n")
    base = _makefile_recipe(r"\$\(BASE\)")
    assert "-e .\n" in base and "[" not in base  # no extras for the demo
    assert '-e ".[dev]"' in _makefile_recipe(r"\$\(STAMP\)")
    assert "$(MAKE) --no-print-directory docs" in _makefile_recipe("test")
    docs = _makefile_recipe("docs")
    assert "sphinx -W" in docs and "docs/_build/html" in docs
    assert "make test" in (REPO / ".ci" / "run").read_text()


def test_docs_carry_no_stale_notes():
    for page in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        text = " ".join(page.read_text().split())
        for phrase in STALE:
            assert phrase not in text, f"{page.name}: {phrase!r}"


def test_pictures_of_readme_and_docs_exist():
    for page in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        prose = re.sub(r"```.*?```|`[^`\n]*`", "", page.read_text(), flags=re.S)
        for target in re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", prose):
            assert (page.parent / target).is_file(), f"{page.name}: missing {target}"
    readme = (REPO / "README.md").read_text()
    assert len(re.findall(r"!\[[^\]]*\]\(docs/images/", readme)) >= 2


def test_reference_documents_every_public_name():
    sys.path.insert(0, str(REPO / "docs" / "_ext"))
    try:
        import optri_reference
    finally:
        sys.path.remove(str(REPO / "docs" / "_ext"))
    pages = optri_reference.reference_pages()
    top = pages["api/optri.rst"]
    for name in optri.__all__:
        if name != "__version__":
            assert re.search(rf"optri\.{re.escape(name)}\b", top), name
    for module in ("optri.data", "optri.holes", "optri.teaching", "optri.config"):
        assert f"api/{module}.rst" in pages
    assert f"   {'optri.data'}\n" in pages["api/index.rst"]
    for command in ("solve", "data", "fill", "batch"):
        assert f"optri {command}\n" in pages["api/cli.rst"]


def test_every_docs_page_is_in_the_site():
    index = (REPO / "docs" / "index.md").read_text()
    assert ":glob:" in index and "\n*\n" in index  # new docs/*.md pages join the Topics
    assert "{include} ../README.md" in index


def test_wheel_holds_the_sample_data_and_licence(tmp_path):
    pytest.importorskip("setuptools", minversion="77")
    source = tmp_path / "optri"
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info")
    shutil.copytree(REPO / "src", source / "src", ignore=ignore)
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(REPO / name, source / name)
    # -v shows the build backend's own output, where setuptools prints its warnings
    command = [sys.executable, "-m", "pip", "wheel", "-v", "--no-deps", "--no-build-isolation"]
    built = subprocess.run(
        [*command, "-w", str(tmp_path / "dist"), str(source)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert built.returncode == 0, built.stderr
    assert "deprecat" not in (built.stdout + built.stderr).lower()  # setuptools' warning box
    (wheel,) = (tmp_path / "dist").glob("optri-*.whl")
    assert wheel.name.startswith(f"optri-{optri.__version__}-py3-none-any")
    with zipfile.ZipFile(wheel) as zf:
        files = set(zf.namelist())
        meta_name = next(f for f in files if f.endswith(".dist-info/METADATA"))
        metadata = zf.read(meta_name).decode()
    for name in optri.data.names():
        assert f"optri/data/{name}" in files
    assert {"optri/py.typed", "optri/teaching/assets/explorer.js"} <= files
    assert any(f.endswith(".dist-info/licenses/LICENSE") for f in files)
    assert "License-Expression: MIT" in metadata
    assert f"Version: {optri.__version__}" in metadata
    assert f"Project-URL: Paper, https://doi.org/{DOI}" in metadata


@pytest.mark.parametrize("script", sorted(p.stem for p in (REPO / "benchmarks").glob("*.py")))
def test_every_benchmark_script_imports(script):
    # scripts run by hand only: an import the code moved away from breaks them unnoticed
    # (bench_simple.py imported require_simple from a package that no longer had it)
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import importlib; "
        "importlib.import_module(sys.argv[2])"
    )
    res = subprocess.run(
        [sys.executable, "-c", code, str(REPO / "benchmarks"), script],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 0, res.stderr.strip().splitlines()[-1:]


@pytest.mark.parametrize(("n", "tile"), [(3, 4), (9, 4), (13, 4), (17, 8), (40, 16), (41, 16)])
def test_bench_parts_counts_near_splits_exactly(n, tile, monkeypatch):
    # bench_parts divides each part's candidates by its seconds: the counts must be exact
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    bench_parts = importlib.import_module("bench_parts")
    near = sum(
        1
        for i in range(n)
        for j in range(i + 2, n)
        for k in range(i + 1, j)
        if k // tile in (i // tile, j // tile)
    )
    assert bench_parts.near_candidates(n, tile) == near


def test_bench_parts_runs_against_the_engines_kernels(monkeypatch):
    # bench_parts calls the fill's private kernels by position: a change of their
    # signatures must break here, not only when someone next profiles the fill
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))
    bench_parts = importlib.import_module("bench_parts")
    parts = bench_parts.profile(150, 1)
    assert list(parts) == ["whole", "edge weights", "far products", "near splits"]
    assert all(0 < seconds < 60 for seconds in parts.values())


def test_readme_is_for_users():
    readme = (REPO / "README.md").read_text()
    assert len(readme.splitlines()) <= 300
    for section in ("## Install", "## Quick start", "## The command line", "## Speed"):
        assert section in readme
    for group in ("students", "GIS", "meshes", "contours"):
        assert re.search(rf"^## For {group}", readme, re.M), group
    # the speed section is one table and the command that reproduces it
    speed = readme.split("## Speed", 1)[1].split("\n## ", 1)[0]
    assert speed.count("\n|---") == 1 and "optri bench" in speed


#: Words of a lab notebook: machines, dates, the jargon of the benchmarking sessions.
HISTORY = re.compile(
    r"\b(EPYC|Xeon|spells?\b|probe-tagged|20\d\d-\d\d-\d\d)|\bturns\b(?= (tagged|between))"
)


def test_code_states_contracts_not_history():
    """Docstrings and comments outside the compiled engines keep no lab notes."""
    ported = ("engines", "simple", "holes")  # rewritten with the compiled core
    found = []
    for path in sorted((REPO / "src" / "optri").rglob("*.py")):
        if path.relative_to(REPO / "src" / "optri").parts[0] in ported:
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if HISTORY.search(line.replace("spell_note", "").replace("SPELL_", "")):
                found.append(f"{path.relative_to(REPO)}:{number}: {line.strip()}")
    assert found == [], "\n".join(found)


def test_performance_log_is_dated():
    log = (REPO / "docs" / "performance-log.md").read_text()
    dates = re.findall(r"^## (\d{4}-\d\d-\d\d)", log, re.M)
    assert dates and dates == sorted(dates)  # oldest first
