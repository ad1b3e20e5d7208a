"""
Contour stack to a closed surface
=================================

Four slices: one contour below, two above (a branching). Matched contours are
joined by optimal tilings (least total area), the branches merge through a
bridged contour half-way, and the ends are closed by optimal caps.
"""

import matplotlib.pyplot as plt
import numpy as np

import optri


def ring(cx, cy, r, k):
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    return np.c_[cx + r * np.cos(t), cy + 0.8 * r * np.sin(t)]


stack = [
    (0.0, [ring(0, 0, 2.0, 28)]),
    (1.0, [ring(0, 0, 2.2, 30)]),
    (2.0, [ring(-1.2, 0, 1.0, 20), ring(1.3, 0, 0.9, 18)]),
    (3.0, [ring(-1.4, 0.2, 0.9, 18), ring(1.5, -0.1, 0.7, 16)]),
]
mesh = optri.contours_to_mesh(stack)
mesh.check()  # closed, manifold, outward normals

fig = plt.figure(figsize=(6, 4.5))
ax = fig.add_subplot(projection="3d")
mesh.plot(ax=ax)
ax.set_title(f"{len(mesh.faces)} triangles, volume {mesh.volume:.2f}")
ax.set_axis_off()
plt.show()
