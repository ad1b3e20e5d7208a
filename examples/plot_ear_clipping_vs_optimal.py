"""
Ear clipping versus the optimum on a real ring
==============================================

Mainland Italy's outline from Natural Earth (65 vertices, bundled as
``italy.geojson``), triangulated three ways: by ear clipping (mapbox-earcut, the
triangulator behind many map renderers), by optri's exact minimum-weight
triangulation (least total diagonal length) and by optri's bottleneck
triangulation that minimizes the largest angle of any triangle. Ear clipping is
fast and valid but blind to shape: long slivers; the optimal triangulations are
exact for their objectives over *every* triangulation of this concave ring.
"""

import matplotlib.pyplot as plt
import numpy as np

import optri

# %%
# The ring, in longitude scaled by the cosine of the mean latitude, so lengths
# (in degrees of latitude) and angles are those of the map (an equirectangular
# projection).
lonlat = optri.io.read_polygon(optri.data.path("italy.geojson"))
xy = lonlat * [np.cos(np.radians(lonlat[:, 1].mean())), 1.0]


def diagonal_length(points, triangles):
    """Total length of the diagonals: (sum of triangle perimeters - ring perimeter) / 2."""
    p = points[triangles]
    sides = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).sum()
    ring = np.linalg.norm(points - np.roll(points, 1, axis=0), axis=1).sum()
    return (sides - ring) / 2


def largest_angle(points, triangles):
    """The largest interior angle of any triangle, in degrees."""
    p = points[triangles]
    a = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
    b = np.linalg.norm(p[:, 2] - p[:, 0], axis=1)
    c = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    cosines = [(b**2 + c**2 - a**2) / (2 * b * c), (a**2 + c**2 - b**2) / (2 * a * c)]
    cosines.append((a**2 + b**2 - c**2) / (2 * a * b))
    return np.degrees(np.arccos(np.clip(np.min(cosines), -1, 1)))


# %%
# Ear clipping, the least total diagonal length, the smallest largest angle.
try:
    import mapbox_earcut

    flat = mapbox_earcut.triangulate_float64(xy, np.array([len(xy)], dtype=np.uint32))
    ear = flat.reshape(-1, 3).astype(np.int64)
except ImportError:  # pip install 'optri[compare]' for the comparison
    ear = None
mwt = optri.triangulate(xy, weight="diagonal")
bottleneck = optri.triangulate(xy, weight="max_angle", objective="max")

panels = [("ear clipping (mapbox-earcut)", ear)] if ear is not None else []
panels += [("optri: least diagonal length", mwt.triangles)]
panels += [("optri: smallest largest angle", bottleneck.triangles)]
fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 5.2))
for ax, (name, tris) in zip(np.atleast_1d(axes), panels):
    ax.fill(xy[:, 0], xy[:, 1], color="#e8f0fb")
    ax.triplot(xy[:, 0], xy[:, 1], tris, color="#31588a", linewidth=0.7)
    ax.plot(*np.vstack([xy, xy[:1]]).T, color="black", linewidth=1.2)
    ax.set_title(
        f"{name}\ndiagonal length {diagonal_length(xy, tris):.1f}, "
        f"largest angle {largest_angle(xy, tris):.0f}°",
        fontsize=10,
    )
    ax.set_aspect("equal")
    ax.set_axis_off()
fig.tight_layout()

# %%
# The exact optimum's total is never above ear clipping's, by construction:
if ear is not None:
    print(f"ear clipping: {diagonal_length(xy, ear):.2f}, optimal: {mwt.weight:.2f}")
