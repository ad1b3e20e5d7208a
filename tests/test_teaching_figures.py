"""Figures 2 and 3, the recursion tree, the board, and Trace.animate."""

import math
import shutil

import numpy as np
import pytest

import optri
from optri.drawing import save_figure
from optri.teaching import (
    Board,
    cell_scheme,
    plot_cell_scheme,
    plot_recursion_tree,
    recursion_tree,
    trace,
)
from optri.teaching.tree import layout

PENTAGON = [5, 1, 5, 1, 5]


def test_cell_scheme_is_the_papers_figure_2():
    general = cell_scheme()
    texts = [[t for t, _ in row] for row in general]
    assert texts[0] == ["0", "w[1,2]", "w[1,3]", "⋯", "w[1,n-2]", "Opt w", "X"]
    assert texts[-1] == ["|vnv1|", "|vnv2|", "|vnv3|", "⋯", "|vnvn-2|", "|vnvn-1|", "0"]
    assert [row[-1][0] for row in general[:-1]] == ["X", "X", "X", "⋮", "X", "X"]
    five = cell_scheme(5)
    assert [t for t, _ in five[0]] == ["0", "w[1,2]", "w[1,3]", "Opt w", "X"]
    assert five[4][1] == ("|v5v2|", "lower")
    # every upper cell but the optimum names w[r, c]; every lower one the chord v_r v_c
    for r, row in enumerate(five):
        for c, (text, part) in enumerate(row):
            if part == "upper":
                assert text == f"w[{r + 1},{c + 1}]"
            if part == "lower":
                assert text == f"|v{r + 1}v{c + 1}|" and r > c
    with pytest.raises(optri.OptriError):
        cell_scheme(2)


def test_recursion_tree_of_the_memoized_pentagon():
    t = trace(PENTAGON, "product")
    root = recursion_tree(t.events)
    nodes = list(root.walk())
    assert len(nodes) == t.counts()["call"] == 21
    status = [n.status for n in nodes]
    assert status.count("computed") == t.counts()["store"] == 6
    # memo hits on sub-polygons: requested again after being stored (CLRS Fig. 15.7 shading)
    pruned = sorted((n.i, n.j) for n in nodes if n.status == "hit")
    assert pruned == [(0, 2), (1, 3), (2, 4)]
    assert status.count("side") == 12
    assert (root.i, root.j, root.value, root.k) == (0, 4, 35.0, 1)
    assert [(c.i, c.j) for c in root.children] == [(0, 1), (1, 4), (0, 2), (2, 4), (0, 3), (3, 4)]
    pos = layout(root)
    leaves = sorted(pos[id(n)][0] for n in nodes if not n.children)
    assert leaves == list(range(len(leaves)))
    for n in nodes:  # a parent sits over its children, one level up
        for c in n.children:
            assert pos[id(c)][1] == pos[id(n)][1] + 1
        if n.children:
            xs = [pos[id(c)][0] for c in n.children]
            assert min(xs) <= pos[id(n)][0] <= max(xs)


def test_naive_tree_has_no_pruned_leaves_and_3_to_the_n_calls():
    root = recursion_tree(trace(PENTAGON, "product", method="naive").events)
    nodes = list(root.walk())
    assert len(nodes) == 27 and not any(n.status == "hit" for n in nodes)


def test_table_trace_has_no_recursion_tree():
    with pytest.raises(optri.OptriError, match="no call"):
        recursion_tree(trace(PENTAGON, "product", method="table").events)
    with pytest.raises(optri.OptriError, match="closes no open call"):
        recursion_tree([("store", 0, 2, 1, 1.0)])


def test_figures_draw(tmp_path):
    save_figure(plot_cell_scheme(), str(tmp_path / "f2.png"))
    save_figure(plot_cell_scheme(6), str(tmp_path / "f2_6.png"))
    ax = plot_recursion_tree(trace(PENTAGON, "product"))
    assert "21 calls" in ax.get_title() and "3 answered" in ax.get_title()
    texts = [t.get_text() for t in ax.texts]
    assert "1..4\n35" in texts and texts.count("1..1") == 3  # the side A1, three times
    save_figure(ax, str(tmp_path / "f3.png"))
    for name in ("f2.png", "f2_6.png", "f3.png"):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"


def test_board_replays_to_the_final_table():
    t = trace(PENTAGON, "product", method="table")
    b = Board(t.n)
    for e in t.events:
        b.apply(e)
    texts = b.cell_texts()
    expected = optri.drawing.table_cells(optri.triangulate(PENTAGON, "product", method="memo"))[0]
    assert texts == expected  # the paper's Table 1, cell by cell
    assert dict(b.counts) == {k: v for k, v in t.counts().items() if v}


def _frames(path):
    from PIL import Image

    with Image.open(path) as im:
        return im.n_frames


def test_gif_has_one_frame_per_event_shown(tmp_path):
    pytest.importorskip("PIL")
    t = trace(PENTAGON, "product")
    out = t.animate(tmp_path / "stores.gif", kinds=("store",), dpi=50)
    assert _frames(out) == len(t.frames(("store",))) == (4 * 3) // 2 + 2  # stores, start, end
    t4 = trace(np.array([[0, 0], [2, 0], [3, 2], [0, 2]], float))
    out = t4.animate(tmp_path / "square.gif", dpi=50)
    assert _frames(out) == 1 + math.comb(4, 3) + 3 + 1  # start, candidates, stores, traced back


def test_animate_refuses_bad_targets(tmp_path, monkeypatch):
    t = trace(PENTAGON, "product")
    with pytest.raises(optri.OptriError, match=".gif or .mp4"):
        t.animate(tmp_path / "x.png")
    with pytest.raises(optri.OptriError, match="unknown event kind"):
        t.animate(tmp_path / "x.gif", kinds=("stores",))
    monkeypatch.setattr(optri.config, "ANIMATE_MAX_FRAMES", 10)
    with pytest.raises(optri.TableTooLargeError, match="ANIMATE_MAX_FRAMES"):
        t.animate(tmp_path / "x.gif")
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(optri.MissingDependencyError, match="ffmpeg"):
        t.animate(tmp_path / "x.mp4")
    assert not list(tmp_path.iterdir())  # nothing half-written


@pytest.mark.skipif(shutil.which("ffprobe") is None, reason="ffmpeg not installed")
def test_mp4_with_ffmpeg(tmp_path):
    import subprocess

    out = trace(PENTAGON, "product").animate(tmp_path / "p.mp4", kinds=("store",), dpi=50)
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
         "-show_entries", "stream=nb_read_frames", "-of", "csv=p=0", str(out)],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    assert int(probe.stdout.strip()) == 6 + 2  # the stores, the empty table, the traceback
