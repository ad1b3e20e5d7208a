import numpy as np
import pytest

import optri
from optri.drawing.table import table_cells


def test_table1_upper_part_cell_by_cell():
    t = optri.triangulate([5, 1, 5, 1, 5], "product", method="memo")
    cells, marks = table_cells(t, "paper")
    assert cells[0] == ["0", "25", "10", "35", "X"]
    assert cells[1][2:] == ["5", "10", "X"]
    assert cells[2][3:] == ["25", "X"]
    # below the diagonal: adjacent pairs and candidate splits, the optimum starred
    assert [cells[r][r - 1] for r in range(1, 5)] == ["(2,1)", "(3,2)", "(4,3)", "(5,4)"]
    assert cells[4][0].replace("*", "") == "2,3,4"
    assert cells[3][1] == "3*" and cells[4][1] == "3,4*"
    assert cells[4][0].count("*") == 1


def test_vertex_style_is_consistent():
    t = optri.triangulate([5, 1, 5, 1, 5], "product", method="table")
    cells, _ = table_cells(t, "vertex", base=0)  # the API's vertex numbers
    assert cells[0][4] == "35" and cells[4][0] == "1"
    cells, _ = table_cells(t, "vertex")  # the paper's labels, one more
    assert cells[0][4] == "35" and cells[4][0] == "2"


def test_no_table_error_and_plot():
    ang = np.linspace(0, 2 * np.pi, 6, endpoint=False)
    t = optri.triangulate(np.column_stack((np.cos(ang), np.sin(ang))), method="brute")
    with pytest.raises(optri.OptriError, match="no table"):
        optri.format_table(t)
    t2 = optri.triangulate([5, 1, 5, 1, 5], "product", method="memo")
    from optri.drawing import plot_table

    ax = plot_table(t2)
    cells, _ = table_cells(t2, "paper")
    celld = ax.tables[0].get_celld()
    drawn = [[celld[r + 1, c].get_text().get_text() for c in range(5)] for r in range(5)]
    assert drawn == cells and drawn[0][3] == "35"  # row 0 of the drawing: column labels
    assert [celld[0, c].get_text().get_text() for c in range(5)] == ["1", "2", "3", "4", "5"]
    ax = t2.plot()
    assert len(ax.lines) == len(t2.diagonals) + 1  # one line per diagonal, one for the boundary
    assert "product sum = 35" in ax.get_title()
