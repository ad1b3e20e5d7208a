"""The explorer page: self-contained HTML, the CLI, and the page in a real browser.

The browser tests drive Chromium from the system packages with Playwright (never a
downloaded browser); they skip when either is missing (``make test`` installs both).
"""

import json
import re
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from optri import config
from optri.cli import main
from optri.teaching import explore, pseudocode, trace

PENTAGON = [5, 1, 5, 1, 5]
OCTAGON = "examples/octagon.csv"


def page_json(html):
    m = re.search(r'<script id="optri-data" type="application/json">(.*?)</script>', html, re.S)
    return json.loads(m.group(1))


def test_page_is_self_contained():
    html = explore(PENTAGON, "product")
    assert html.startswith("<!DOCTYPE html>")
    for banned in ("<link", " src=", "@import", "url(", "https:", "//cdn", "<iframe"):
        assert banned not in html, banned
    # the only "http:" is the SVG namespace name the script creates elements in
    assert set(re.findall(r"http://[^\"' ]+", html)) == {"http://www.w3.org/2000/svg"}
    assert html.count("<script") == 2 and html.count("<style>") == 1


def test_page_data_is_the_traces():
    data = page_json(explore(PENTAGON, "product", method="table"))
    assert data["start"] == "table" and list(data["traces"]) == ["table", "memo", "naive"]
    for method, t in data["traces"].items():
        ref = trace(PENTAGON, "product", method=method)
        assert t["counts"] == ref.counts()
        assert len(t["events"]) == len(ref.events)
        assert t["events"][-1] == [3, 0, 4, 1, 35]  # the store of (0, n-1)
        lines, at = pseudocode(method)
        assert t["code"] == lines and t["lines"] == at
    assert data["labels"] == ["v1=5", "v2=1", "v3=5", "v4=1", "v5=5"]
    # naive only joins when asked for or when small
    big = page_json(explore(np.arange(8.0) + 1, "product"))
    assert list(big["traces"]) == ["memo", "table"]


def test_pseudocode_marks_the_line_of_each_event():
    lines, at = pseudocode("memo")
    assert lines[at["call"]] == "OPT(i, j):"
    assert "OPT(i, k) + OPT(k+1, j)" in lines[at["candidate"]]
    assert "return w[i, j]" in lines[at["store"]]
    lines, at = pseudocode("table", "max")
    assert "max(w[i, k], w[k+1, j]" in lines[at["candidate"]] and "hit" in at and "call" not in at
    lines, at = pseudocode("naive")
    assert "i = j" in lines[at["callSide"]] and "hit" not in at


def test_page_refuses_large_polygons(monkeypatch):
    monkeypatch.setattr(config, "EXPLORE_MAX_N", 6)
    with pytest.raises(optri.TableTooLargeError, match="EXPLORE_MAX_N"):
        explore(np.arange(7.0) + 1, "product")
    with pytest.raises(optri.EngineUnavailableError):
        explore(PENTAGON, "product", method="fast")


def test_trace_repr_html_embeds_the_explorer():
    html = trace(PENTAGON, "product")._repr_html_()
    assert html.startswith("<iframe srcdoc=") and "window.optri" in html
    assert "<script" not in html  # escaped inside srcdoc, so the notebook's page is untouched


def test_cli_explore(tmp_path):
    out = tmp_path / "p.html"
    res = CliRunner().invoke(main, ["explore", "5,1,5,1,5", "-w", "product", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "explorer written" in res.output
    assert page_json(out.read_text("utf-8"))["traces"]["memo"]["events"][-1][-1] == 35
    res = CliRunner().invoke(main, ["explore", OCTAGON, "--method", "naive", "-o", str(out)])
    assert res.exit_code == 0 and page_json(out.read_text("utf-8"))["start"] == "naive"


def test_cli_explore_errors(tmp_path):
    out = tmp_path / "p.html"
    res = CliRunner().invoke(main, ["explore", "missing.csv", "-o", str(out)])
    assert res.exit_code == 2 and res.output.startswith("optri: error:")
    values = ",".join(["2"] * (config.NAIVE_MAX_N + 1))
    res = CliRunner().invoke(
        main, ["explore", values, "-w", "product", "-m", "naive", "-o", str(out)]
    )
    assert res.exit_code == 2 and "NAIVE_MAX_N" in res.output
    assert len(res.output.strip().splitlines()) == 1
    assert not out.exists()


# ---- the page in a real browser -------------------------------------------------------


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.skip("no chromium on the PATH (apt-get install chromium)")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(
            executable_path=exe,
            args=[
                "--no-sandbox",
                "--disable-gpu",
                "--disable-background-networking",
                "--disable-dev-shm-usage",
            ],
        )
        yield b
        b.close()


def open_page(browser, path):
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    problems, requests = [], []
    page.on("console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else 0)
    page.on("pageerror", lambda e: problems.append(str(e)))
    page.on("request", lambda r: requests.append(r.url))
    page.goto(path.as_uri())
    return page, problems, requests


def test_browser_pentagon(browser, tmp_path):
    path = tmp_path / "pentagon.html"
    explore(PENTAGON, "product", path=path)
    page, problems, requests = open_page(browser, path)
    api = "window.optri"
    s = page.evaluate(f"{api}.state()")
    assert (s["step"], s["total"], s["cell"], s["method"]) == (0, 52, None, "memo")
    s = page.evaluate(f"{api}.step()")
    assert (s["step"], s["kind"], s["cell"]) == (1, "call", [0, 4])
    s = page.evaluate(f"{api}.step()")
    assert (s["step"], s["kind"], s["cell"]) == (2, "call", [0, 1])
    assert page.evaluate(f"{api}.back()")["step"] == 1
    s = page.evaluate(f"{api}.last()")
    assert (s["step"], s["kind"], s["cell"], s["value"]) == (52, "store", [0, 4], 35)
    assert s["counts"] == {"call": 21, "hit": 15, "candidate": 10, "store": 6}
    assert page.inner_text("#optimum") == "35"
    assert "Optimum w[1,4] = 35" in page.inner_text("#status")
    # the optimal chords are highlighted: w[1,4], w[2,4], w[2,3] above, their splits below
    assert page.eval_on_selector_all("td.opt", "els => els.length") == 6
    assert page.inner_text("tr:nth-child(2) td:nth-child(5)") == "35"  # printed cell (1, 4)
    shot = tmp_path / "pentagon.png"
    page.screenshot(path=str(shot), full_page=True)
    _looks_like_a_page(shot)
    # hover a cell: its sub-polygon and optimal triangles
    page.hover('td[data-i="1"][data-j="4"]')
    assert "w[2,4] = 10" in page.inner_text("#status")
    assert page.eval_on_selector_all("#poly polygon.opt", "els => els.length") == 2
    assert page.evaluate(f"{api}.first()")["step"] == 0
    assert problems == [] and requests == [path.as_uri()]


def test_browser_switches_orders_and_plays(browser, tmp_path):
    path = tmp_path / "octagon.html"
    explore(OCTAGON, method="table", path=path)
    ref = optri.triangulate(OCTAGON, method="memo").weight
    page, problems, _ = open_page(browser, path)
    assert page.evaluate("window.optri.methods") == ["table", "memo"]
    s = page.evaluate("window.optri.last()")
    assert s["method"] == "table" and s["cell"] == [0, 7] and s["counts"]["call"] == 0
    assert s["value"] == pytest.approx(ref, rel=1e-12)
    page.evaluate("window.optri.method('memo')")
    s = page.evaluate("window.optri.state()")
    assert (s["method"], s["step"], s["total"]) == ("memo", 0, len(trace(OCTAGON).events))
    page.select_option("#method", "table")
    assert page.evaluate("window.optri.state().method") == "table"
    page.evaluate("window.optri.play()")
    page.wait_for_function("window.optri.state().step >= 2", timeout=10_000)
    page.click("#play")  # pause
    paused = page.evaluate("window.optri.state().step")
    page.wait_for_timeout(600)
    assert page.evaluate("window.optri.state().step") == paused
    page.click("#last")
    assert page.evaluate("window.optri.state().value") == pytest.approx(ref, rel=1e-12)
    assert problems == []


def _looks_like_a_page(png):
    from PIL import Image

    with Image.open(png) as im:
        assert im.size[0] >= 1000 and im.size[1] >= 400
        colours = im.convert("RGB").getcolors(maxcolors=1 << 20)
    assert colours is not None and len(colours) > 50  # text, table colours, the polygon
