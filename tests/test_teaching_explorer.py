"""The explorer page: self-contained HTML, the CLI, and the page in a real browser.

The browser tests drive Chromium from the system packages with Playwright (never a
downloaded browser); they skip when either is missing (``make test`` installs both).
The page runs the DP itself; its events are checked against optri's own traces (the
Python engines), event by event. The documentation's screenshots come from
``docs/make_images.py``.
"""

import json
import math
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


def star(n, spike=0.4):
    """A non-convex star: every other vertex pushed out (some chords outside)."""
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1 + spike * (np.arange(n) % 2)
    return np.column_stack((r * np.cos(ang), r * np.sin(ang)))


def wobbly(n):
    """A convex-ish n-gon with unequal sides (no ties to hide a wrong order)."""
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.05 * np.sin(3 * np.arange(n))
    return np.column_stack((1000 * np.cos(ang), 700 * np.sin(ang)))


def test_page_data_is_the_problem():
    data = page_json(explore(PENTAGON, "product", method="table"))
    assert data["start"] == "table" and list(data["methods"]) == ["table", "memo", "naive"]
    for method, t in data["methods"].items():
        assert t["counts"] == trace(PENTAGON, "product", method=method).counts()
        lines, at = pseudocode(method)
        assert t["code"] == lines and t["lines"] == at
    assert data["labels"] == ["p0=5", "p1=1", "p2=5", "p3=1", "p4=5"]
    assert data["values"] == PENTAGON and data["mask"] is None
    # every triangle (i, k, j) in the order i, j, k: p_i p_k p_j
    want = [
        PENTAGON[i] * PENTAGON[k] * PENTAGON[j]
        for i in range(5)
        for j in range(i + 2, 5)
        for k in range(i + 1, j)
    ]
    assert data["tw"] == want and len(want) == math.comb(5, 3)
    # naive only joins when asked for or when small
    big = page_json(explore(np.arange(8.0) + 1, "product"))
    assert list(big["methods"]) == ["memo", "table"]


def test_page_data_of_a_non_convex_polygon_carries_its_chord_mask():
    poly = star(10)
    data = page_json(explore(poly))
    ok = optri.solve.build_problem(
        optri.solve.load_polygon(poly), "perimeter", "sum"
    ).allowed_rows()
    assert data["mask"] == "".join(
        "1" if ok[i][j] else "0" for i in range(10) for j in range(i + 1, 10)
    )
    assert "0" in data["mask"] and len(data["tw"]) < math.comb(10, 3)


@pytest.mark.parametrize(
    "n,weight,limit", [(5, "product", 60_000), (40, "product", 400_000), (40, "perimeter", 400_000)]
)
def test_page_size_stays_small(n, weight, limit):
    poly = list(range(1, n + 1)) if weight == "product" else wobbly(n)
    html = explore(poly, weight)
    assert len(html.encode("utf-8")) < limit
    assert len(page_json(html)["tw"]) == math.comb(n, 3)


def test_user_text_is_data_never_markup():
    name = "{{js}}</script><script>alert(1)</script>{{data}}"
    w = optri.weights.custom_weight(lambda i, k, j: float(i + k + j), name=name)
    html = explore(PENTAGON, w)
    assert html.count("<script") == 2 and html.count("</script>") == 2
    assert html.count("window.optri = {") == 1  # the script once: "{{js}}" in the name stays text
    # the name is escaped in the title and passed as JSON data to the script
    assert "<title>optri explorer: n = 5, {{js}}&lt;/script&gt;&lt;script&gt;alert(1)" in html
    assert page_json(html)["weight"] == name
    page = optri.teaching.explorer.explorer_page([trace(PENTAGON, "product")], title="<{{css}}>")
    assert "<h1>&lt;{{css}}&gt;</h1>" in page and page.count("<style>") == 1


def test_page_refuses_large_polygons(monkeypatch):
    monkeypatch.setattr(config, "EXPLORE_MAX_N", 6)
    with pytest.raises(optri.TableTooLargeError, match="EXPLORE_MAX_N"):
        explore(np.arange(7.0) + 1, "product")
    with pytest.raises(optri.EngineUnavailableError):
        explore(PENTAGON, "product", method="fast")
    t = trace(np.arange(7.0) + 1, "product")
    with pytest.raises(optri.TableTooLargeError, match="EXPLORE_MAX_N"):
        t.explorer_html()
    # the notebook repr keeps the same limit: a summary, not a page
    html = t._repr_html_()
    assert "<iframe" not in html and "EXPLORE_MAX_N" in html and len(html) < 1000


def test_page_refuses_values_it_cannot_hold_exactly():
    with pytest.raises(optri.OptriError, match="2\\*\\*53"):
        explore([2**40, 3, 2**20, 5], "product")


def test_pseudocode_marks_the_line_of_each_event():
    lines, at = pseudocode("memo")
    assert lines[at["call"]] == "OPT(i, j):"
    assert "OPT(i, k) + OPT(k+1, j)" in lines[at["candidate"]]
    assert "return w[i, j]" in lines[at["store"]]
    lines, at = pseudocode("table", "max")
    assert "max(w[i, k], w[k+1, j]" in lines[at["candidate"]] and "hit" in at and "call" not in at
    lines, at = pseudocode("naive")
    assert "i = j" in lines[at["callSide"]] and "hit" not in at


def test_trace_repr_html_embeds_the_explorer():
    html = trace(PENTAGON, "product")._repr_html_()
    assert html.startswith("<iframe srcdoc=") and "window.optri" in html
    assert "<script" not in html  # escaped inside srcdoc, so the notebook's page is untouched


def test_cli_explore(tmp_path):
    out = tmp_path / "p.html"
    res = CliRunner().invoke(main, ["explore", "5,1,5,1,5", "-w", "product", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "explorer written" in res.output
    data = page_json(out.read_text("utf-8"))
    assert data["methods"]["memo"]["counts"] == trace(PENTAGON, "product").counts()
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
    s = page.evaluate(f"{api}.step()")
    assert (s["kind"], s["cell"]) == ("side", [0, 1])  # reading a side is not a hit
    assert page.evaluate(f"{api}.back()")["step"] == 2
    s = page.evaluate(f"{api}.last()")
    assert (s["step"], s["kind"], s["cell"], s["value"]) == (52, "store", [0, 4], 35)
    # one definition of a hit: the three grey leaves of Figure 3
    assert s["counts"] == {"call": 21, "side": 12, "hit": 3, "candidate": 10, "store": 6}
    assert page.inner_text("#optimum") == "35"
    assert "Optimum w[1,4] = 35" in page.inner_text("#status")
    assert page.eval_on_selector_all("td.opt", "els => els.length") == 6
    assert page.inner_text("tr:nth-child(2) td:nth-child(5)") == "35"  # printed cell (1, 4)
    # the paper's arithmetic for each candidate of the root
    assert page.evaluate(f"{api}.arithmetic(0, 4, 1)") == (
        "w[1,4] = w[1,1] + w[2,4] + p0\u00b7p1\u00b7p4 = 0 + 10 + 25 = 35"
    )
    assert page.evaluate(f"{api}.arithmetic(0, 4, 2)") == (
        "w[1,4] = w[1,2] + w[3,4] + p0\u00b7p2\u00b7p4 = 25 + 25 + 125 = 175"
    )
    page.hover('td[data-i="1"][data-j="4"]')
    assert "w[2,4] = 10" in page.inner_text("#status")
    assert page.eval_on_selector_all("#poly polygon.opt", "els => els.length") == 2
    # the cell list: one row per stored cell; a click expands the cell's candidates
    assert page.eval_on_selector_all("#cells .cell", "els => els.length") == 6
    page.click("#cells .cell:last-child .cellhead")
    cands = page.eval_on_selector_all("#cells .cand", "els => els.map(e => e.textContent)")
    assert len(cands) == 3 and cands[0].endswith("= 35") and cands[1].endswith("= 175")
    assert page.evaluate(f"{api}.state()")["step"] == 52
    _shot(page, tmp_path, "explorer_end.png")
    assert page.evaluate(f"{api}.first()")["step"] == 0
    assert problems == [] and requests == [path.as_uri()]


@pytest.mark.parametrize(
    "poly,weight,objective",
    [
        (PENTAGON, "product", "sum"),
        (OCTAGON, "perimeter", "sum"),
        (star(12), "perimeter", "sum"),  # chords outside: the mask
        (star(11), "area", "max"),
        (star(10), ("perimeter", "area"), ("sum", "max")),  # lexicographic
        (list(range(1, 11)), "product", "naive-first"),  # the naive order, asked for at 10
    ],
)
def test_browser_runs_the_engines_own_steps(browser, tmp_path, poly, weight, objective):
    """The page's run equals optri's traces event by event: kind, cell, split and value."""
    path = tmp_path / "p.html"
    first = "naive" if objective == "naive-first" else "memo"
    objective = "sum" if first == "naive" else objective
    explore(poly, weight, objective, method=first, path=path)
    page, problems, _ = open_page(browser, path)
    methods = page.evaluate("window.optri.methods")
    assert methods[0] == first and "table" in methods
    for method in methods:
        ours = page.evaluate(f"window.optri.events('{method}')")
        ref = [
            [e.kind, e.i, e.j, e.k, _plain(e.value)]
            for e in trace(poly, weight, objective, method).events
        ]
        assert [[a, b, c, d, _plain(v)] for a, b, c, d, v in ours] == ref
    assert problems == []


def _js_number(v):
    """A number as the page prints it: 6 significant digits, integers whole."""
    x = float(f"{float(v):.6g}")
    return str(int(x)) if x.is_integer() else repr(x)


def _plain(v):
    if v is None:
        return None
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    return float(v)


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


def test_browser_forty_vertices(browser, tmp_path):
    n = 40
    poly = wobbly(n)
    path = tmp_path / "forty.html"
    explore(poly, path=path)
    assert path.stat().st_size < 400_000
    page, problems, _ = open_page(browser, path)
    t = trace(poly)
    api = "window.optri"
    assert page.evaluate(f"{api}.state()")["total"] == len(t.events)
    assert page.evaluate(f"{api}.cells().length") == (n - 1) * (n - 2) // 2
    # next store: the first cell stored in memo order, then the next
    stores = [s for s, e in enumerate(t.events) if e.kind == "store"]
    assert page.evaluate(f"{api}.nextStore()")["step"] == stores[0] + 1
    assert page.evaluate(f"{api}.nextStore()")["step"] == stores[1] + 1
    # next cell: the next candidate in another cell
    s = page.evaluate(f"{api}.nextCell()")
    here = t.events[s["step"] - 1]
    assert here.kind == "candidate" and (here.i, here.j) != (
        t.events[stores[1]].i,
        t.events[stores[1]].j,
    )
    # the page fits a 1280-px screen; the table scrolls in its own box to the cell in view
    assert page.evaluate("document.documentElement.scrollWidth") <= 1280
    page.evaluate(f"{api}.goTo({stores[-2] + 1})")  # a long chord: far right in the table
    box = page.evaluate(
        "(() => { const b = document.getElementById('tablebox'); "
        "return [b.scrollLeft, b.clientWidth, b.scrollWidth]; })()"
    )
    assert box[2] > box[1] and box[0] > 0
    cur = page.eval_on_selector(
        "td.cur",
        "e => { const r = e.getBoundingClientRect(), "
        "b = document.getElementById('tablebox').getBoundingClientRect(); "
        "return r.left >= b.left && r.right <= b.right; }",
    )
    assert cur
    before = page.evaluate("document.getElementById('table').offsetWidth")
    page.click("#zoomout")
    assert page.evaluate("document.getElementById('table').offsetWidth") < before
    s = page.evaluate(f"{api}.last()")
    assert s["value"] == pytest.approx(t.optimum, rel=1e-12)
    assert s["counts"] == t.counts()
    # a geometric candidate's sum names its weight: w[1,39] split at v2
    first = next(e for e in t.events if e.kind == "candidate" and (e.i, e.j, e.k) == (0, 39, 1))
    right = next(e for e in t.events if e.kind == "store" and (e.i, e.j) == (1, 39))
    text = page.evaluate(f"{api}.arithmetic(0, 39, 1)")
    assert text.startswith("w[1,39] = w[1,1] + w[2,39] + perimeter(v1,v2,v40) = 0 + ")
    assert text.endswith(f" = {_js_number(first.value)}")
    assert f" + {_js_number(right.value)} + " in text
    _shot(page, tmp_path, "explorer_n40.png")
    assert problems == []


def test_browser_predict_the_split(browser, tmp_path):
    path = tmp_path / "pentagon.html"
    explore(PENTAGON, "product", method="table", path=path)
    page, problems, _ = open_page(browser, path)
    api = "window.optri"
    page.check("#predict")
    s = page.evaluate(f"{api}.last()")  # stops before the first cell with two splits
    assert s["asking"] == [0, 3] and "Predict" in s["status"]
    assert page.eval_on_selector_all("#choices button", "els => els.map(e => e.textContent)") == [
        "v2",
        "v3",
    ]
    # w[1,3] = min(w[1,1] + w[2,3] + 5*1*1, w[1,2] + w[3,3] + 5*5*1) = 10 at v2
    page.click("#choices button:nth-child(1)")
    s = page.evaluate(f"{api}.state()")
    assert s["score"] == [1, 1] and s["asking"] is None and s["kind"] == "store"
    s = page.evaluate(f"{api}.nextStore()")
    assert s["asking"] == [1, 4]
    assert page.evaluate(f"{api}.answer(2)") is False  # w[2,4]: 5 at v4, v3 gives 10
    assert page.evaluate(f"{api}.state()")["score"] == [1, 2]
    # clicking a vertex answers too
    page.evaluate(f"{api}.nextStore()")
    assert page.evaluate(f"{api}.state()")["asking"] == [0, 4]
    _shot(page, tmp_path, "explorer_predict.png")
    page.click('#poly circle[data-v="1"]')
    assert page.evaluate(f"{api}.state()")["score"] == [2, 3]
    assert page.inner_text("#score") == "score 2 / 3"
    assert problems == []


def test_browser_students_own_input(browser, tmp_path):
    path = tmp_path / "pentagon.html"
    explore(PENTAGON, "product", path=path)
    page, problems, _ = open_page(browser, path)
    api = "window.optri"
    values = [3, 7, 2, 9, 4, 6, 1]
    page.fill("#values", ", ".join(map(str, values)))
    page.click("#solve")
    s = page.evaluate(f"{api}.last()")
    assert s["value"] == optri.triangulate(values, "product").weight
    assert s["counts"] == trace(values, "product").counts()
    assert page.evaluate(f"{api}.state().n") == 7
    page.fill("#values", "1, 2")
    page.click("#solve")
    assert "3 to 40" in page.inner_text("#problem")
    problems.clear()  # the refusal is reported on the console too
    # clicked vertices, perimeter weight: the DP reruns on the student's polygon
    path = tmp_path / "octagon.html"
    explore(OCTAGON, path=path)
    page, problems, _ = open_page(browser, path)
    page.click("#draw")
    box = page.eval_on_selector(
        "#poly", "e => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.width]; }"
    )
    clicks = [(60, 60), (250, 50), (280, 200), (170, 120), (120, 270), (40, 200)]  # not convex
    for x, y in clicks:
        page.mouse.click(box[0] + x * box[2] / 340, box[1] + y * box[2] / 340)
    page.click("#solve")
    s = page.evaluate(f"{api}.last()")
    assert s["n"] == 6
    # the same polygon in optri (y down on screen: flipped, so counter-clockwise)
    clicked = page.evaluate(f"{api}.points()")
    assert np.allclose(sorted(clicked), sorted(clicks), atol=1.0)  # within a pixel
    pts = [(x, -y) for x, y in clicked]
    ref = optri.triangulate(pts, "perimeter")
    assert s["value"] == pytest.approx(ref.weight, rel=1e-12)
    assert page.evaluate(f"{api}.state().counts") == trace(pts).counts()
    assert problems == []


def _shot(page, tmp_path, name):
    shot = tmp_path / name
    page.screenshot(path=str(shot), full_page=True)
    _looks_like_a_page(shot)


def _looks_like_a_page(png):
    from PIL import Image

    with Image.open(png) as im:
        assert im.size[0] >= 1000 and im.size[1] >= 400
        colours = im.convert("RGB").getcolors(maxcolors=1 << 20)
    assert colours is not None and len(colours) > 50  # text, table colours, the polygon
