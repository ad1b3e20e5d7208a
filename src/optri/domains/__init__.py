"""Polygons with holes ("polygonal domains"), triangulated exactly.

:func:`triangulate_domain` finds the optimal triangulation of a polygon with
holes for any weight that sums (or maximizes) over triangles. The candidate
triangles are the variables of a 0/1 program (each boundary edge covered
once, each diagonal used on both sides or neither) that HiGHS solves; before
that, diagonals crossed by no other are fixed, they cut the domain into
independent blocks, and every block without a hole goes to the dynamic
program instead. A time limit turns the answer into a labelled heuristic
with a proven bound. :func:`optri.triangulate` sends polygons with holes here.
"""

from __future__ import annotations

from .candidates import Candidates, find_candidates, valid_diagonals
from .domain import Domain, as_domain
from .random_domains import random_domain
from .solver import METHODS, triangulate_domain

__all__ = [
    "METHODS",
    "Candidates",
    "Domain",
    "as_domain",
    "find_candidates",
    "random_domain",
    "triangulate_domain",
    "valid_diagonals",
]
