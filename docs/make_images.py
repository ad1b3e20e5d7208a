"""Regenerate the pictures of the README and docs/learn.md into docs/images/.

    python docs/make_images.py        (from the repository root)

Figures 2 and 3 and the GIF need matplotlib and pillow; the explorer screenshots need
Playwright and Chromium from the system packages (skipped with a message without them);
the README's two pictures are the gallery scripts' figures (examples/plot_*.py, the same
that ``make docs`` runs), which need the compare and mesh extras.
``mesh_refill_peers.png`` (docs/mesh.md) refills one hole with optri, CGAL and MeshLib
through ``benchmarks/bench_refill.py``; it needs the bench extra (the peers' wheels) and is
skipped with a message without them.
Every PNG is reduced to a small palette so the repository stays light.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

OUT = Path(__file__).resolve().parent / "images"
PENTAGON = [5, 1, 5, 1, 5]
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: README (and docs) picture <- the gallery script that draws it
README_PICTURES = {
    "italy_earcut_vs_optimal.png": "plot_ear_clipping_vs_optimal.py",
    "mesh_hole_filled.png": "plot_mesh_hole.py",
    "mesh_refine_fair.png": "plot_refine_and_fair.py",
    "mesh_hole_with_island.png": "plot_hole_with_island.py",
    "contours_branching.png": "plot_contours.py",
}


def _shrink(path: Path, colours: int = 96) -> None:
    from PIL import Image

    with Image.open(path) as im:
        small = im.convert("RGB").quantize(colours, method=Image.Quantize.FASTOCTREE)
    small.save(path, optimize=True)


def figures() -> None:
    """Figures 2 and 3 (memo and naive) and the pentagon's GIF."""
    from optri.drawing import save_figure
    from optri.teaching import plot_cell_scheme, plot_recursion_tree, trace

    save_figure(plot_cell_scheme(), str(OUT / "fig2_cell_scheme.png"))
    save_figure(plot_recursion_tree(trace(PENTAGON, "product")), str(OUT / "fig3_memo_tree.png"))
    naive = trace(PENTAGON, "product", method="naive")
    save_figure(plot_recursion_tree(naive), str(OUT / "fig3_naive_tree.png"))
    for name in ("fig2_cell_scheme.png", "fig3_memo_tree.png", "fig3_naive_tree.png"):
        _shrink(OUT / name)
    trace(PENTAGON, "product").animate(OUT / "pentagon_memo.gif", fps=1.5, dpi=72)


def screenshots() -> None:
    """The explorer page in Chromium at 1280 px: the pentagon, n = 40, predict mode."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("playwright missing: explorer screenshots skipped", file=sys.stderr)
        return
    exe = shutil.which("chromium")
    if exe is None:
        print("chromium missing: explorer screenshots skipped", file=sys.stderr)
        return
    import numpy as np

    from optri.teaching import explore

    tmp = Path(tempfile.mkdtemp())
    explore(PENTAGON, "product", path=tmp / "pentagon.html")
    explore(PENTAGON, "product", method="table", path=tmp / "table.html")
    ang = np.linspace(0, 2 * np.pi, 40, endpoint=False) + 0.05 * np.sin(3 * np.arange(40))
    explore(np.column_stack((1000 * np.cos(ang), 700 * np.sin(ang))), path=tmp / "forty.html")
    args = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=args)
        page = browser.new_page(viewport={"width": 1280, "height": 640})
        page.goto((tmp / "pentagon.html").as_uri())
        for _ in range(42):  # the candidate w[1,3] via v2: a sub-polygon and its triangle
            page.evaluate("window.optri.step()")
        page.screenshot(path=str(OUT / "explorer_step.png"))
        page.evaluate("window.optri.last()")
        page.click("#cells .cell:last-child .cellhead")  # the root's candidates, with sums
        page.screenshot(path=str(OUT / "explorer_end.png"))
        page.goto((tmp / "table.html").as_uri())
        page.check("#predict")
        page.evaluate("window.optri.last()")
        page.evaluate("window.optri.answer(1)")
        page.evaluate("window.optri.nextStore()")
        page.screenshot(path=str(OUT / "explorer_predict.png"))
        page.set_viewport_size({"width": 1280, "height": 800})
        page.goto((tmp / "forty.html").as_uri())
        page.evaluate("window.optri.goTo(40000)")
        page.screenshot(path=str(OUT / "explorer_n40.png"))
        browser.close()
    for name in (
        "explorer_step.png",
        "explorer_end.png",
        "explorer_predict.png",
        "explorer_n40.png",
    ):
        _shrink(OUT / name)


def readme_pictures() -> None:
    """Run each gallery script behind a README picture and save its last figure."""
    import runpy

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for name, script in README_PICTURES.items():
        plt.close("all")
        runpy.run_path(str(EXAMPLES / script), run_name="__main__")
        plt.gcf().savefig(OUT / name, dpi=80, bbox_inches="tight")
        _shrink(OUT / name, colours=64)
    plt.close("all")


def refill_pictures() -> None:
    """One hole cut from a sphere; optri's flat and faired patches, CGAL's and MeshLib's."""
    import importlib.util

    try:
        import CGAL  # noqa: F401
        import meshlib  # noqa: F401
    except ImportError:
        print("cgal or meshlib missing: mesh_refill_peers.png skipped", file=sys.stderr)
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from optri import fill_holes

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_refill.py"
    spec = importlib.util.spec_from_file_location("bench_refill", path)
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    sys.modules["bench_refill"] = bench
    spec.loader.exec_module(bench)
    sphere = bench.icosphere(4)
    top = int(np.argmax(sphere.vertices @ np.array([0.45, -0.3, 0.84])))
    centre = sphere.vertices[top]

    class Pick:  # the random centre of cut_hole, made the vertex nearest that direction
        def integers(self, n: int) -> int:
            return top

    hole = bench.cut_hole(sphere, 70, Pick())
    (fv, ff), _ = fill_holes((hole.vertices, hole.faces))
    flat = bench.Refill("flat", fv, ff, len(hole.faces), 0.0)
    panels = [
        (f"the hole ({hole.edges} edges)", None),
        ("optri, optimal patch", flat),
        ("optri, refine + fair=1", bench.refill_optri(hole, 1)),
        ("optri, refine + fair=2", bench.refill_optri(hole, 2)),
        ("CGAL refine + fair", bench.refill_cgal(hole)),
        ("MeshLib fillHoleNicely", bench.refill_meshlib(hole)),
    ]
    fig = plt.figure(figsize=(12, 6.4))
    for i, (title, r) in enumerate(panels):
        ax = fig.add_subplot(2, 3, i + 1, projection="3d")
        v, f, old = (hole.vertices, hole.faces, len(hole.faces)) if r is None else (
            r.vertices, r.faces, r.old_faces)
        near = np.linalg.norm(v[f].mean(axis=1) - centre, axis=1) < 1.0
        colours = np.where(np.arange(len(f)) >= old, "#f28e2b", "#c9d6ea")[near]
        ax.add_collection3d(Poly3DCollection(
            v[f[near]], facecolors=colours, edgecolors="#4a4a4a", linewidths=0.25))
        if r is not None and r.method != "flat":
            new = r.vertices[len(hole.vertices):]
            rms = float(np.sqrt(np.mean((np.linalg.norm(new, axis=1) - 1) ** 2)))
            title += f"\nRMS to the sphere {rms:.3f}"
        ax.set_title(title, fontsize=11)
        lim = centre + np.array([[-0.5], [0.5]])
        ax.set(xlim=lim[:, 0], ylim=lim[:, 1], zlim=lim[:, 2])
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=14, azim=-56)
        ax.set_axis_off()
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.93, wspace=0, hspace=0.12)
    fig.savefig(OUT / "mesh_refill_peers.png", dpi=80, bbox_inches="tight")
    plt.close(fig)
    _shrink(OUT / "mesh_refill_peers.png", colours=64)


def main() -> None:
    """Write every picture and list the sizes."""
    OUT.mkdir(exist_ok=True)
    figures()
    screenshots()
    readme_pictures()
    refill_pictures()
    for f in sorted(OUT.iterdir()):
        print(f"{f.name}: {f.stat().st_size // 1024} KiB")


if __name__ == "__main__":
    main()
