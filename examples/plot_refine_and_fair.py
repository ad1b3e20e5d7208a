"""
Refining and fairing a hole's patch
===================================

A cap cut off an icosphere leaves a hole of 36 edges. The optimal patch alone uses
only the hole's own vertices, so it spans the hole nearly flat. With
``refine=True`` the patch gets the density of the mesh around it (Liepa's centroid
splits and edge relaxation), and with ``fair=2`` its new vertices minimise the
variation of curvature with the rest of the mesh fixed: the cap comes back close to
the sphere. New faces are drawn in orange. Needs ``pip install 'optri[mesh]'``.
"""

import matplotlib.pyplot as plt
import numpy as np
import trimesh
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import optri

sphere = trimesh.creation.icosphere(subdivisions=3)
keep = sphere.vertices[sphere.faces].mean(axis=1)[:, 2] < 0.6
holed = trimesh.Trimesh(sphere.vertices, sphere.faces[keep], process=False)
flat, _ = optri.fill_holes(holed)
faired, (record,) = optri.fill_holes(holed, refine=True, fair=2)
new = faired.vertices[len(holed.vertices) :]
print(record.detail())
print("largest distance of a new vertex to the sphere:",
      float(np.abs(np.linalg.norm(new, axis=1) - 1).max()))

# %%
# Side by side, seen from the side of the cut.
ELEV, AZIM = 12, -60
fig = plt.figure(figsize=(9, 4.6))
for index, (title, mesh) in enumerate(
    [("optimal patch alone", flat), ("refined and faired (fair=2)", faired)]
):
    ax = fig.add_subplot(1, 2, index + 1, projection="3d")
    first_new = len(holed.faces)
    colours = np.where(np.arange(len(mesh.faces)) >= first_new, "#f28e2b", "#c9d6ea")
    ax.add_collection3d(
        Poly3DCollection(
            mesh.vertices[mesh.faces], facecolors=colours, edgecolors="#4a4a4a", linewidths=0.3
        )
    )
    ax.set(xlim=(-0.9, 0.9), ylim=(-0.9, 0.9), zlim=(-0.9, 0.9))
    fig.text(0.25 + 0.5 * index, 0.06, title, ha="center", fontsize=12)
    ax.view_init(elev=ELEV, azim=AZIM)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
fig.subplots_adjust(left=0, right=1, bottom=0, top=1, wspace=0)
