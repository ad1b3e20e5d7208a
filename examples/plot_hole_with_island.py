"""
A hole with an island
=====================

A band cut out of a sphere leaves two boundary loops: the rim of the hole and the
border of the cap left standing above it, an *island* inside the hole's loop. Filled
loop by loop (``islands=False``), each loop gets its own flat cap: two closed pieces
that no longer touch. With islands (the default), ``fill_holes`` finds the cap's loop
inside the hole's loop (winding number in the hole's best-fit plane) and fills the band
between them as one connected, manifold patch (after Zou, Ju and Carr's triangulation
of several 3-D polygons); ``refine=True, fair=1`` then gives it the mesh's density and
the sphere's curvature. New faces are drawn in orange. Needs
``pip install 'optri[mesh]'``.
"""

import matplotlib.pyplot as plt
import numpy as np
import trimesh
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import optri

# a band cut out of a sphere: the cap above it is left standing inside the hole
sphere = trimesh.creation.icosphere(subdivisions=3)
z = sphere.triangles_center[:, 2]
holed = trimesh.Trimesh(sphere.vertices, sphere.faces[(z < 0.25) | (z > 0.75)], process=False)
apart, apart_records = optri.fill_holes(holed, islands=False)
joined, (record,) = optri.fill_holes(holed, refine=True, fair=1)
print(len(apart_records), "patches without islands;", record.detail())
pieces = trimesh.graph.connected_components(joined.face_adjacency, min_len=1, engine="scipy")
print("closed:", joined.is_watertight, "; pieces:", len(pieces))

# %%
# Side by side: loop by loop, and the hole with its island.
fig = plt.figure(figsize=(9, 4.4))
for index, (title, mesh) in enumerate(
    [("islands=False: two caps", apart), ("with the island: one patch, faired", joined)]
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
    fig.text(0.25 + 0.5 * index, 0.08, title, ha="center", fontsize=12)
    ax.view_init(elev=8, azim=-60)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
fig.subplots_adjust(left=0, right=1, bottom=0, top=1, wspace=0)
