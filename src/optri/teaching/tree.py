"""The recursion tree of a traced top-down evaluation (the paper's Figure 3).

Each call is a node; its children are the calls it makes, in order. A call
answered from the table (a memo hit) is a pruned leaf, the recursion it saves
never happens; a side (j = i + 1) is a base case.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from typing import Any

from ..errors import OptriError

__all__ = ["Node", "layout", "recursion_tree"]


@dataclass(eq=False)
class Node:
    """One call of the recursion on chord (i, j).

    ``status`` is ``"computed"`` (the cell was evaluated: it has children),
    ``"hit"`` (answered from the table: a pruned leaf) or ``"side"`` (a
    polygon side: the base case). ``value`` is the cost the call returned and
    ``k`` the optimal split of a computed cell.
    """

    i: int
    j: int
    status: str
    value: Any = None
    k: int | None = None
    children: list[Node] = field(default_factory=list)

    def walk(self) -> Iterator[Node]:
        """The node and its descendants, depth first (call order)."""
        stack = [self]
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(node.children))

    def size(self) -> int:
        """Number of calls in the subtree."""
        return sum(1 for _ in self.walk())


def recursion_tree(events: Iterable[Any]) -> Node:
    """Build the call tree from the events of a ``"memo"`` or ``"naive"`` trace.

    Raises
    ------
    OptriError
        The events hold no call (a bottom-up ``"table"`` trace) or do not nest.

    Examples
    --------
    >>> from optri.teaching import trace
    >>> root = recursion_tree(trace([5, 1, 5, 1, 5], "product").events)
    >>> root.size(), sum(n.status == "hit" for n in root.walk())    # 3 subtrees pruned
    (21, 3)
    """
    root: Node | None = None
    stack: list[Node] = []
    side: Node | None = None  # the last side called, waiting for its hit (memo)
    for e in events:
        kind, i, j = e[0], e[1], e[2]
        if kind == "call":
            node = Node(i, j, "side" if j - i == 1 else "computed")
            if stack:
                stack[-1].children.append(node)
            elif root is None:
                root = node
            else:
                raise OptriError("the events hold two roots: not a single recursion")
            if node.status == "side":
                side = node
            else:
                stack.append(node)
        elif kind == "side":
            if side is None or (side.i, side.j) != (i, j):
                raise OptriError(f"a side read of ({i}, {j}) follows no call of it")
            side.value, side = e[4], None
        elif kind == "hit":
            if stack and (stack[-1].i, stack[-1].j) == (i, j) and not stack[-1].children:
                node = stack.pop()
                node.status, node.value = "hit", e[4]
            else:
                raise OptriError(f"a hit on ({i}, {j}) follows no call of it")
        elif kind == "store":
            if not stack or (stack[-1].i, stack[-1].j) != (i, j):
                raise OptriError(f"a store of ({i}, {j}) closes no open call")
            node = stack.pop()
            node.value, node.k = e[4], e[3]
    if root is None:
        raise OptriError("these events hold no call: a bottom-up trace has no recursion tree")
    return root


def layout(root: Node) -> dict[int, tuple[float, int]]:
    """``{id(node): (x, depth)}``: leaves at consecutive x, a parent over its children.

    >>> from optri.teaching import trace
    >>> root = recursion_tree(trace([5, 1, 5, 1, 5], "product").events)
    >>> pos = layout(root)
    >>> pos[id(root)][1], max(d for _, d in pos.values())
    (0, 3)
    """
    pos: dict[int, tuple[float, int]] = {}
    leaves = 0
    # iterative post-order: (node, depth, children done?)
    stack: list[tuple[Node, int, bool]] = [(root, 0, False)]
    while stack:
        node, depth, done = stack.pop()
        if not node.children:
            pos[id(node)] = (float(leaves), depth)
            leaves += 1
        elif done:
            xs = [pos[id(c)][0] for c in node.children]
            pos[id(node)] = ((xs[0] + xs[-1]) / 2, depth)
        else:
            stack.append((node, depth, True))
            stack.extend((c, depth + 1, False) for c in reversed(node.children))
    return pos
