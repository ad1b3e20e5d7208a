"""
The paper's table, recomputed
=============================

Selimi et al. (2019) illustrate memoization on a pentagon with vertex values
p = 5, 1, 5, 1, 5 and the product weight p_i p_k p_j: its Table 1 holds the
optimal weight of every sub-polygon above the diagonal and the candidate split
vertices below it, the optimal one starred. optri prints it in the paper's
layout (:func:`optri.format_table`) and draws it (:func:`optri.drawing.plot_table`).
"""

import optri
from optri.drawing import plot_table

t = optri.triangulate([5, 1, 5, 1, 5], weight="product", method="memo")
print(optri.format_table(t))
print("optimal weight:", t.weight, "- weight evaluations:", t.stats["weight_evaluations"])

# %%
# The same table as a figure: weights above the diagonal, splits below, the
# optimal split of each cell highlighted.
ax = plot_table(t)
ax.set_title("Table 1 of the paper, recomputed (optimum 35)")
