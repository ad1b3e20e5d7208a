"""
Filling the holes of a mesh
===========================

The bundled ``sphere_two_holes.obj`` is an icosphere with two holes (16 and 12
boundary edges). :func:`optri.fill_holes` closes each with the patch that is
optimal for Liepa's objective (first the largest dihedral angle, then the total
area), searched exactly over every triangulation of the hole, and reports each
hole. The new faces are drawn in orange. Needs ``pip install 'optri[mesh]'``.
"""

import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import optri

mesh = optri.io.read_mesh(optri.data.path("sphere_two_holes.obj"))
filled, report = optri.fill_holes(mesh)
for record in report:
    print(record.to_dict())

# %%
# The mesh before and after, seen from above both holes. Faces turned away
# from the viewer are drawn dark: through a hole one sees the inside of the
# sphere. The patch faces are those after the input's own.
ELEV, AZIM = 38, -35
toward_viewer = np.array(
    [
        np.cos(np.radians(ELEV)) * np.cos(np.radians(AZIM)),
        np.cos(np.radians(ELEV)) * np.sin(np.radians(AZIM)),
        np.sin(np.radians(ELEV)),
    ]
)


def colours(faces, first_new):
    """Light for faces seen from outside, orange for new ones, dark for the inside."""
    corners = filled.vertices[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    front = normals @ toward_viewer > 0
    new = np.arange(len(faces)) >= first_new
    return np.where(~front, "#2f2f2f", np.where(new, "#f28e2b", "#c9d6ea"))


fig = plt.figure(figsize=(9, 4.8))
for index, (title, faces) in enumerate(
    [("input: two holes", mesh.faces), ("filled by optri", filled.faces)]
):
    ax = fig.add_subplot(1, 2, index + 1, projection="3d")
    ax.add_collection3d(
        Poly3DCollection(
            filled.vertices[faces],
            facecolors=colours(faces, len(mesh.faces)),
            edgecolors="#4a4a4a",
            linewidths=0.3,
        )
    )
    ax.set(xlim=(-0.8, 0.8), ylim=(-0.8, 0.8), zlim=(-0.8, 0.8))
    fig.text(0.25 + 0.5 * index, 0.08, title, ha="center", fontsize=12)
    ax.view_init(elev=ELEV, azim=AZIM)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
fig.subplots_adjust(left=0, right=1, bottom=0, top=1, wspace=0)
