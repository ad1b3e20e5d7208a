"""Teaching the paper's DP: traces, Figures 2 and 3, animations and the explorer page.

:func:`trace` runs a Python engine (``"memo"``, the paper's Algorithm 3.1;
``"table"``, the bottom-up square matrix; ``"naive"``, the recursion without a
table) and records every call, look-up, candidate and store; a
:class:`Trace` draws its recursion tree (:func:`plot_recursion_tree`, the
paper's Figure 3), animates the table filling (:meth:`Trace.animate`) and
replays in a browser page (:func:`explore`, ``optri explore``).
:func:`plot_cell_scheme` draws the paper's Figure 2.
"""

from __future__ import annotations

from .board import Board, value_text
from .explorer import explorer_page, pseudocode
from .figures import cell_scheme, plot_cell_scheme, plot_recursion_tree
from .trace import KINDS, METHODS, Event, Trace, explore, trace
from .tree import Node, recursion_tree

__all__ = [
    "KINDS",
    "METHODS",
    "Board",
    "Event",
    "Node",
    "Trace",
    "cell_scheme",
    "explore",
    "explorer_page",
    "plot_cell_scheme",
    "plot_recursion_tree",
    "pseudocode",
    "recursion_tree",
    "trace",
    "value_text",
]
