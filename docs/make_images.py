"""Regenerate the pictures of the README and docs/learn.md into docs/images/.

    python docs/make_images.py        (from the repository root)

Figures 2 and 3 and the GIF need matplotlib and pillow; the explorer screenshots need
Playwright and Chromium from the system packages (skipped with a message without them);
the README's two pictures are the gallery scripts' figures (examples/plot_*.py, the same
that ``make docs`` runs), which need the compare and mesh extras.
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
#: README picture <- the gallery script that draws it
README_PICTURES = {
    "italy_earcut_vs_optimal.png": "plot_ear_clipping_vs_optimal.py",
    "mesh_hole_filled.png": "plot_mesh_hole.py",
    "mesh_refine_fair.png": "plot_refine_and_fair.py",
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


def main() -> None:
    """Write every picture and list the sizes."""
    OUT.mkdir(exist_ok=True)
    figures()
    screenshots()
    readme_pictures()
    for f in sorted(OUT.iterdir()):
        print(f"{f.name}: {f.stat().st_size // 1024} KiB")


if __name__ == "__main__":
    main()
