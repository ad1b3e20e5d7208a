"""Reproduction of Selimi et al. (2019): Tables 2–4, Figures 1–7, on this machine.

:func:`optri.paper.report.write_report` regenerates the whole comparison (also
``optri paper -o DIR``); the modules compute one piece each:
:mod:`~optri.paper.published` (the paper's printed numbers and formulas),
:mod:`~optri.paper.tables` (Tables 2 and 3), :mod:`~optri.paper.timing`
(Table 4), :mod:`~optri.paper.figures` (PNGs), :mod:`~optri.paper.report`
(report.md and the notes on the paper).
"""

from __future__ import annotations

from .report import PaperConfig, write_report

__all__ = ["PaperConfig", "write_report"]
