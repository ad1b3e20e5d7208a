"""The paper's printed numbers and its operation-count formulas (Eqs. 5–7).

Selimi, Krrabaj, Saračević, Pepić, "Memoization method for storing
minimum-weight triangulation of convex polygon", Computer Science 20(2), 2019,
https://doi.org/10.7494/csci.2019.20.2.3193
"""

from __future__ import annotations

from ..enumeration.counting import catalan

__all__ = [
    "OCTAGON",
    "PENTAGON_VALUES",
    "TABLE2",
    "TABLE3",
    "TABLE4",
    "eq5",
    "eq6",
    "eq7",
]

#: The pentagon of Table 1 and Steps 1–4: matrix dimensions p0..p4 (5x1 and 1x5 matrices).
PENTAGON_VALUES = (5.0, 1.0, 5.0, 1.0, 5.0)

#: A convex octagon for Figures 1 and 4 (the paper gives no coordinates; this is
#: the project's examples/octagon.csv).
OCTAGON = (
    (4.0, 0.0),
    (9.0, 1.0),
    (12.0, 5.0),
    (11.0, 10.0),
    (7.0, 13.0),
    (2.0, 12.0),
    (-1.0, 8.0),
    (0.0, 3.0),
)

#: Table 2 as printed: (row, diagonals with 1-based labels, printed weight).
TABLE2 = (
    (1, ((1, 3), (3, 5)), 71),
    (2, ((1, 4), (2, 4)), 61),
    (3, ((2, 4), (2, 5)), 35),
    (4, ((2, 5), (3, 5)), 51),
    (5, ((1, 4), (1, 3)), 76),
)
#: Table 2 marks row 3 ({δ24, δ25}) optimal; the text says Optw = {δ14, δ24}.
TABLE2_MARKED_ROW = 3
TEXT_OPTIMUM = ((1, 4), (2, 4))

#: Table 3 as printed: n -> (HN, SM, MM, S(HN,MM), S(SM,MM), R(SM,MM)).
TABLE3 = {
    7: (45, 35, 15, 30, 20, 2.33),
    8: (161, 56, 21, 140, 35, 2.67),
    9: (588, 84, 28, 560, 56, 3.00),
    10: (2178, 120, 36, 2142, 84, 3.33),
    11: (8151, 165, 45, 8106, 120, 3.67),
    12: (30745, 220, 55, 30690, 165, 4.00),
    13: (116688, 286, 66, 116622, 220, 4.33),
    14: (445094, 364, 78, 445016, 286, 4.67),
}

#: Table 4 as printed (units not stated): n -> (T, MwtS(A), MwtS(B), MwtM(A), MwtM(B), R(A), R(B)).
TABLE4 = {
    5: (5, 0.01, 1.7, 0.01, 0.8, 1.00, 2.13),
    6: (14, 0.03, 2.4, 0.02, 1.4, 1.50, 1.71),
    7: (42, 0.09, 2.8, 0.05, 2.1, 1.80, 1.33),
    8: (132, 0.12, 3.7, 0.09, 3.0, 1.33, 1.23),
    9: (429, 0.19, 5.2, 0.10, 4.7, 1.90, 1.11),
    10: (1430, 0.27, 14.8, 0.13, 13.3, 2.08, 1.11),
    11: (4862, 0.41, 27.4, 0.19, 24.9, 2.16, 1.10),
    12: (16796, 0.62, 48.7, 0.31, 44.1, 2.00, 1.10),
    13: (58786, 1.04, 64.6, 0.63, 59.3, 1.65, 1.09),
    14: (208012, 1.59, 85.5, 1.04, 78.5, 1.53, 1.09),
}


def eq5(n: int) -> int:
    """HN_w = (2n - 5) C(n-3) + (2n - 3) C(n-2): Hurtado–Noy operations (Eq. 5).

    >>> [eq5(n) for n in (5, 7, 9)]
    [45, 588, 8151]
    """
    return (2 * n - 5) * catalan(n - 3) + (2 * n - 3) * catalan(n - 2)


def eq6(n: int) -> int:
    """V_n = sum_{i=1}^{n-2} i (n - i - 1): square-matrix weights (Eq. 6), = C(n, 3).

    >>> [eq6(n) for n in (5, 6, 7)]
    [10, 20, 35]
    """
    return sum(i * (n - i - 1) for i in range(1, n - 1))


def eq7(n: int) -> int:
    """MM = (n - 2)(n - 1) / 2: the memoization count of Eq. 7 (= table cells).

    >>> eq7(7)
    15
    """
    return (n - 2) * (n - 1) // 2
