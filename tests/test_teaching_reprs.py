"""Notebook reprs (never an empty picture, no raw sentinels) and CLRS's chain tables."""

import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri import config
from optri.cli import main


@pytest.mark.parametrize(
    "vertices,weight",
    [
        ([5, 1, 5, 1, 5], "product"),  # the paper's pentagon: values, no geometry
        ([[0, 0, 0], [1, 0, 1], [1, 1, 0], [0, 1, 1]], "area"),  # a 3-D quadrilateral
        ([[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]], "perimeter"),
    ],
)
def test_repr_svg_is_never_empty(vertices, weight):
    t = optri.triangulate(vertices, weight)
    svg = t._repr_svg_()
    assert svg.startswith("<svg") and svg.endswith("</svg>")
    assert svg.count("<polygon") == t.n - 2 + 1  # the triangles and the outline
    outline = re.findall(r'points="([^"]*)"', svg)[-1].split()
    points = {tuple(float(v) for v in p.split(",")) for p in outline}
    assert len(points) == t.n  # a real drawing: n distinct corners inside the image
    assert all(0 <= v <= 300 for p in points for v in p)


def test_value_svg_labels_each_vertex_with_its_value():
    svg = optri.triangulate([5, 1, 5, 1, 5], "product")._repr_svg_()
    assert re.findall(r">([^<]+)</text>", svg) == ["0: 5", "1: 1", "2: 5", "3: 1", "4: 5"]


def test_repr_html_shows_the_table_beside_the_drawing():
    t = optri.triangulate([5, 1, 5, 1, 5], "product", method="memo")
    html = t._repr_html_()
    assert html.index("<svg") < html.index("<table")
    cells = re.findall(r"<td[^>]*>([^<]*)</td>", html)
    assert cells == [c for row in optri.drawing.table_cells(t)[0] for c in row]
    assert "-1" not in cells and "35" in cells and "2*,3,4" in cells


def test_repr_html_without_a_sentinel_on_unreachable_chords():
    # triangle (1, 2, 3) forbidden: chord (1, 3) has no finite split, its raw split is -1
    def w(i, k, j):
        return math.inf if (i, k, j) == (1, 2, 3) else 1.0

    t = optri.triangulate([[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]], w, method="memo")
    assert t.table[3, 1] == -1 and t.weight == 3.0
    assert not re.search(r">[^<]*-1[^<]*<", t._repr_html_())
    assert "-1" not in optri.format_table(t, style="vertex")


def test_repr_html_notes_a_missing_or_large_table(monkeypatch):
    t = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], method="fast")
    assert t.table is None and "No table kept" in t._repr_html_() and "<svg" in t._repr_html_()
    monkeypatch.setattr(config, "HTML_TABLE_MAX_N", 4)
    t = optri.triangulate([1, 2, 3, 4, 5], "product", method="memo")
    assert "<table" not in t._repr_html_() and "HTML_TABLE_MAX_N" in t._repr_html_()


CLRS_M = {  # CLRS 3rd ed., Figure 15.5: m[i, j] for 30, 35, 15, 5, 10, 20, 25
    (1, 2): 15750, (1, 3): 7875, (1, 4): 9375, (1, 5): 11875, (1, 6): 15125,
    (2, 3): 2625, (2, 4): 4375, (2, 5): 7125, (2, 6): 10500,
    (3, 4): 750, (3, 5): 2500, (3, 6): 5375,
    (4, 5): 1000, (4, 6): 3500,
    (5, 6): 5000,
}  # fmt: skip
CLRS_S = {
    (1, 2): 1, (1, 3): 1, (1, 4): 3, (1, 5): 3, (1, 6): 3,
    (2, 3): 2, (2, 4): 3, (2, 5): 3, (2, 6): 3,
    (3, 4): 3, (3, 5): 3, (3, 6): 3,
    (4, 5): 4, (4, 6): 5,
    (5, 6): 5,
}  # fmt: skip


def test_chain_tables_are_clrs_figure_15_5():
    c = optri.matrix_chain([30, 35, 15, 5, 10, 20, 25])
    assert c.m.shape == c.s.shape == (7, 7)
    assert {k: int(c.m[k]) for k in CLRS_M} == CLRS_M
    assert {k: int(c.s[k]) for k in CLRS_S} == CLRS_S
    assert all(c.m[i, i] == 0 for i in range(1, 7))
    assert not np.triu(c.s, 0)[np.tril_indices(7)].any()  # nothing on or below the diagonal


def _textbook(d):
    """MATRIX-CHAIN-ORDER (CLRS 15.2), strict < so the first best k is kept."""
    size = len(d) - 1
    m = [[0] * (size + 1) for _ in range(size + 1)]
    s = [[0] * (size + 1) for _ in range(size + 1)]
    for length in range(2, size + 1):
        for i in range(1, size - length + 2):
            j = i + length - 1
            m[i][j] = None
            for k in range(i, j):
                q = m[i][k] + m[k + 1][j] + d[i - 1] * d[k] * d[j]
                if m[i][j] is None or q < m[i][j]:
                    m[i][j], s[i][j] = q, k
    return m, s


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(1, 40), min_size=3, max_size=10))
def test_chain_tables_equal_matrix_chain_order(dims):
    c = optri.matrix_chain(dims)
    m, s = _textbook(dims)
    size = len(dims) - 1
    for i in range(1, size + 1):
        for j in range(i, size + 1):
            assert c.m[i, j] == m[i][j]
            if i < j:  # any split of equal cost is optimal; its cost must be the optimum
                k = int(c.s[i, j])
                assert i <= k < j
                assert m[i][k] + m[k + 1][j] + dims[i - 1] * dims[k] * dims[j] == m[i][j]
    assert c.m[1, size] == c.cost


def test_chain_tables_stay_exact_past_int64():
    c = optri.matrix_chain([10**7] * 6)
    assert c.m.dtype == object and c.m[1, 5] == 4 * 10**21


def test_cli_chain_tables():
    res = CliRunner().invoke(main, ["chain", "30", "35", "15", "5", "10", "20", "25", "--tables"])
    assert res.exit_code == 0
    lines = res.output.splitlines()
    i = lines.index("m[i, j]: fewest scalar multiplications for A_i ... A_j (CLRS 15.2)")
    assert lines[i + 2].split() == ["1", "0", "15750", "7875", "9375", "11875", "15125"]
    assert lines[i + 7].split() == ["6", "0"]
    j = next(n for n, line in enumerate(lines) if line.startswith("s[i, j]"))
    assert lines[j + 1].split() == ["2", "3", "4", "5", "6"]
    assert lines[j + 2].split() == ["1", "1", "1", "3", "3", "3"]
    assert lines[j + 5].split() == ["4", "4", "5"]
    res = CliRunner().invoke(main, ["chain", "2", "3", "4", "--tables", "--json"])
    assert json.loads(res.output) == {
        "cost": 24,
        "parenthesization": "(A1A2)",
        "m": [[0, 24], [0, 0]],
        "s": [[0, 1], [0, 0]],
    }
