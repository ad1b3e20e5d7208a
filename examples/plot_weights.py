"""
One polygon, four objectives
============================

The recurrence is the same for every triangle weight and objective: only the
weight function and how weights add up change. The paper's octagon (bundled as
``octagon.csv``) under four of optri's built-in choices.
"""

import math

import matplotlib.pyplot as plt

import optri

octagon = optri.data.path("octagon.csv")
choices = [
    ("perimeter", "sum", "least total perimeter (paper, Eq. 1)", "{:.2f}"),
    ("diagonal", "sum", "least diagonal length (MWT)", "{:.2f}"),
    ("max_angle", "max", "smallest largest angle", "largest angle {:.0f}°"),
    ("min_angle", "max", "largest smallest angle", "smallest angle {:.0f}°"),
]
fig, axes = plt.subplots(1, 4, figsize=(13, 3.9), layout="constrained")
for ax, (weight, objective, title, value) in zip(axes, choices):
    t = optri.triangulate(octagon, weight=weight, objective=objective)
    t.plot(ax=ax)
    # the angle weights are in radians, min_angle negated so that smaller is better
    shown = abs(math.degrees(t.weight)) if "angle" in weight else t.weight
    ax.set_title(f"{title}\n{weight}, {objective}: {value.format(shown)}", fontsize=9)
