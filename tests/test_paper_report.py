import re

import pytest

from optri.paper import published
from optri.paper.report import PaperConfig, write_report
from optri.paper.tables import GEOMETRIC_PENTAGON, markdown_table, table2, table3_row


def test_formulas_match_paper_and_closed_forms():
    from math import comb

    assert published.eq7(7) == 15
    assert published.eq6(7) == 35
    assert [published.eq6(n) for n in (5, 6, 7)] == [10, 20, 35]  # the paper's V5, V6, V7
    for n in range(4, 30):
        assert published.eq6(n) == comb(n, 3)
        assert published.eq7(n) == comb(n - 1, 2)
    # printed HN column = Eq. 5 at n - 2; printed SM = Eq. 6; printed MM = Eq. 7
    for n, (hn, sm, mm, s1, s2, ratio) in published.TABLE3.items():
        assert hn == published.eq5(n - 2)
        assert sm == published.eq6(n) and mm == published.eq7(n)
        assert s1 == hn - mm and s2 == sm - mm and ratio == round(sm / mm, 2)


def test_table4_published_columns_consistent():
    for n, (t, sa, sb, ma, mb, ra, rb) in published.TABLE4.items():
        from optri.enumeration import catalan

        assert t == catalan(n - 2)
        assert abs(sa / ma - ra) < 0.011 and abs(sb / mb - rb) < 0.011


@pytest.mark.parametrize("n", [5, 7, 9])
def test_table3_measured_counts(n):
    row = table3_row(n)
    assert row.hn_operations == published.eq5(n)
    assert row.sm_weight_evaluations == row.mm_weight_evaluations == published.eq6(n)
    assert row.mm_cells == published.eq7(n)
    if row.printed:
        assert row.printed[0] == row.eq5_shifted


def test_table2_product_pentagon():
    rows = table2(published.PENTAGON_VALUES, "product")
    by = {frozenset(r.diagonals): (r.weight, r.optimal) for r in rows}
    got = [by[frozenset(d)] for _, d, _ in published.TABLE2]
    assert got == [(175.0, False), (35.0, True), (35.0, True), (75.0, False), (75.0, False)]
    geo = table2(GEOMETRIC_PENTAGON, "perimeter")
    assert len(geo) == 5 and sum(r.optimal for r in geo) == 1


def test_markdown_table_shape():
    text = markdown_table(["a", "b"], [[1, None], [2, 0.123456]])
    assert text.splitlines()[2:] == ["| 1 | – |", "| 2 | 0.1235 |"]


def test_report_quick(tmp_path):
    path = write_report(tmp_path, PaperConfig.quick())
    text = path.read_text()
    # Table 3 row at n = 7: T, HN ops = Eq.5(7), Eq.5(5) = printed 45, ..., Eq.6 = 35, Eq.7 = 15
    assert re.search(r"\| 7 \| 42 \| 588 \| 588 \| 45 \| 45 \|", text)
    row7 = next(line for line in text.splitlines() if line.startswith("| 7 | 42 | 588"))
    cells = [c.strip() for c in row7.strip("|").split("|")]
    assert cells[8:15] == ["35", "35", "35", "35", "15", "15", "15"]
    assert "## Notes on the paper" in text
    assert "71, 61, 35, 51, 76" in text and "175, 35, 35, 75, 75" in text
    assert "Eq. 5 evaluated at n - 2" in text
    assert "Step 1 typo" in text
    assert "## Machine" in text and "python:" in text and "numpy:" in text
    for name in (
        "fig1_octagon.png",
        "fig2_cell_scheme.png",
        "fig3_recursion_tree.png",
        "fig3_naive_tree.png",
        "fig5_completion_time.png",
        "fig7_ratio.png",
        "table1_pentagon.png",
    ):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"
    # every figure written is embedded in the report, none merely linked
    embedded = re.findall(r"^!\[[^\]]+\]\(([^)]+\.png)\)$", text, flags=re.M)
    assert sorted(embedded) == sorted(p.name for p in tmp_path.glob("*.png"))
    assert not re.search(r"^- \[[^\]]+\]\([^)]+\.png\)", text, flags=re.M)
    # the paper's Table 4 figures are printed beside the measured ones
    assert "| 0.01 | 1.7 | 0.01 | 0.8 |" in text
    # Table 3's S and R: recomputed from the measured counts, equal to the print at n = 7
    assert "| 7 | 30 | 30 | 20 | 20 | 2.33 | 2.33 | 0 | 1.00 |" in text
    assert "they come out as printed at every printed n" in text
    # one run per size: (B) cannot be judged, and the report says so
    assert "one run" in text and "no noise estimate" in text


def test_table4_b_is_named_noise_where_the_pairs_disagree():
    from optri.paper.notes import _timing_notes
    from optri.paper.timing import TimingRow

    noisy = TimingRow(9, 1e-4, 0.10, 5e-5, 0.09, 5, (0.93, 1.2))
    clear = TimingRow(10, 1e-4, 0.12, 5e-5, 0.10, 5, (1.1, 1.3))
    single = TimingRow(11, 1e-4, 0.12, 5e-5, 0.10, 1, (1.2, 1.2))
    assert (noisy.b_is_noise, clear.b_is_noise, single.b_is_noise) == (True, False, None)
    notes = " ".join(_timing_notes([noisy, clear, single]))
    assert "Table 4's (B) is not reproducible" in notes and "At n = 9 (1 of 2 sizes" in notes
    notes = " ".join(_timing_notes([clear]))
    assert "not reproducible" not in notes and "agrees on the faster method" in notes


def test_time_methods_records_the_pairs():
    from optri.paper.timing import time_methods

    row = time_methods(5, repeats=2)
    low, high = row.ratio_b_range
    assert low <= high and low > 0 and row.b_is_noise == (low <= 1.0 <= high)
