"""Project files and packaging: licence, citation, changelog, one version, the wheel, docs.

The wheel test builds optri with ``pip wheel --no-deps --no-build-isolation`` from a
copy of the checkout and inspects it: the compiled core, the sample data, the licence,
the metadata, and no C++ sources. The sdist test builds the source archive through the
backend's own hook; a build without a C++ compiler must fail with one clear line.
"""

from __future__ import annotations

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
    # a licence classifier beside an SPDX expression is refused by PEP 639 backends
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
    requires = PYPROJECT["build-system"]["requires"]
    assert {r.split(">")[0] for r in requires} == {"scikit-build-core", "nanobind"}
    assert PYPROJECT["build-system"]["build-backend"] == "scikit_build_core.build"


def test_one_version_source():
    assert "version" not in PYPROJECT["project"]
    assert "version" in PYPROJECT["project"]["dynamic"]
    version = PYPROJECT["tool"]["scikit-build"]["metadata"]["version"]
    assert version["input"] == "src/optri/_version.py"
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


def test_demo_installs_the_base_package_and_test_builds_the_docs():
    demo = _makefile_recipe("demo")
    assert demo.startswith("demo: $(CORE)\n")  # the core, which needs the base install
    assert _makefile_recipe(r"\$\(CORE\)").startswith("$(CORE): $(BASE) $(CORE_SOURCES)\n")
    base = _makefile_recipe(r"\$\(BASE\)")
    assert "-e .\n" in base and '".[' not in base  # no extras for the demo
    assert '-e ".[dev]"' in _makefile_recipe(r"\$\(STAMP\)")
    assert _makefile_recipe("test").startswith("test: $(STAMP) $(CORE)")
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


def _source_copy(tmp_path: Path) -> Path:
    """The files a build reads, copied: the checkout's own build folders stay out of it."""
    source = tmp_path / "optri"
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "_core*.so", "_core*.pyd")
    shutil.copytree(REPO / "src", source / "src", ignore=ignore)
    for name in ("pyproject.toml", "README.md", "LICENSE", "CMakeLists.txt"):
        shutil.copy(REPO / name, source / name)
    return source


@pytest.mark.slow
def test_wheel_holds_the_core_the_sample_data_and_licence(tmp_path):
    pytest.importorskip("scikit_build_core")
    pytest.importorskip("nanobind")
    source = _source_copy(tmp_path)
    command = [sys.executable, "-m", "pip", "wheel", "-v", "--no-deps", "--no-build-isolation"]
    built = subprocess.run(
        [*command, "-w", str(tmp_path / "dist"), str(source)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert built.returncode == 0, built.stderr[-3000:]
    (wheel,) = (tmp_path / "dist").glob("optri-*.whl")
    assert wheel.name.startswith(f"optri-{optri.__version__}-")
    assert "py3-none-any" not in wheel.name  # a platform wheel: it holds compiled code
    with zipfile.ZipFile(wheel) as zf:
        files = set(zf.namelist())
        meta_name = next(f for f in files if f.endswith(".dist-info/METADATA"))
        metadata = zf.read(meta_name).decode()
    for name in optri.data.names():
        assert f"optri/data/{name}" in files
    assert {"optri/py.typed", "optri/teaching/assets/explorer.js"} <= files
    assert [f for f in files if re.fullmatch(r"optri/_core\..*(so|pyd)", f)]
    assert not [f for f in files if f.endswith((".cpp", ".hpp"))]  # sources stay in the sdist
    assert any(f.endswith(".dist-info/licenses/LICENSE") for f in files)
    assert "License-Expression: MIT" in metadata
    assert f"Version: {optri.__version__}" in metadata
    assert f"Project-URL: Paper, https://doi.org/{DOI}" in metadata
    requires = [ln for ln in metadata.splitlines() if ln.startswith("Requires-Dist: numba")]
    assert requires and all("extra ==" in ln for ln in requires)  # numba is optional


def test_sdist_holds_the_core_sources(tmp_path):
    pytest.importorskip("scikit_build_core")
    source = _source_copy(tmp_path)
    hook = (
        "import sys; from scikit_build_core.build import build_sdist; "
        "print(build_sdist(sys.argv[1]))"
    )
    built = subprocess.run(
        [sys.executable, "-c", hook, str(tmp_path / "dist")],
        cwd=source,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert built.returncode == 0, built.stderr[-3000:]
    (archive,) = (tmp_path / "dist").glob("optri-*.tar.gz")
    import tarfile

    with tarfile.open(archive) as tf:
        names = {n.split("/", 1)[1] for n in tf.getnames() if "/" in n}
    assert {"CMakeLists.txt", "pyproject.toml", "src/core/module.cpp", "src/core/cpu.cpp"} <= names
    assert "src/optri/__init__.py" in names
    assert not [n for n in names if n.endswith((".so", ".pyd"))]


def test_a_build_without_a_compiler_fails_with_one_clear_line(tmp_path):
    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.skip("no cmake here")
    source = _source_copy(tmp_path)
    env = {"PATH": "/usr/bin:/bin", "CXX": str(tmp_path / "no-such-compiler")}
    res = subprocess.run(
        [cmake, "-S", str(source), "-B", str(tmp_path / "build")],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert res.returncode != 0
    assert "optri: no C++17 compiler found" in res.stdout + res.stderr


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
