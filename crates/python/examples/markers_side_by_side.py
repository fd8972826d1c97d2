"""The same 2,000 points drawn by matplotlib's ``Axes.scatter`` and by ``pointillist.points``
with round markers, side by side: docs/images/markers_side_by_side.png (docs/PYTHON.md,
"Markers and sizes").

Both panels are 400 x 400 pixels of the same data range. matplotlib's ``s`` is a marker's area
in points squared; a circle of ``s`` is ``sqrt(s)`` points across, ``sqrt(s) * dpi / 72`` pixels,
which is the ``size`` given to pointillist (``size_units="pixels"``). Colours come from the
same column through the same colormap, opaque, drawn in row order (pointillist's
``blend="alpha"``, whose disc edges are the coverage's alpha).

Usage (from the repository root, with the package and matplotlib installed)::

    python crates/python/examples/markers_side_by_side.py [OUT.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pointillist  # noqa: E402

N = 2000
PIXELS = 400
DPI = 100
S = 36.0  # matplotlib's marker area, points squared: 6 points across

rng = np.random.default_rng(7)
theta = rng.uniform(0, 2 * np.pi, N)
radius = np.sqrt(rng.uniform(0, 1, N))
x = radius * np.cos(theta) + rng.normal(0, 0.05, N)
y = radius * np.sin(theta) * 0.6 + rng.normal(0, 0.05, N)
value = np.hypot(x, y)
RANGE = (-1.3, 1.3)

fig, (left, right) = plt.subplots(1, 2, figsize=(9.6, 4.6), dpi=DPI, layout="constrained")
# matplotlib: the scatter plot at its usual look, on axes whose data area is PIXELS wide.
left.set_box_aspect(1)
left.scatter(x, y, s=S, c=value, cmap="viridis", linewidths=0)
left.set_xlim(RANGE)
left.set_ylim(RANGE)
left.set_facecolor("black")
left.set_title(f"matplotlib scatter(s={S:g}, c=value, cmap='viridis')", fontsize=9)

# pointillist: the same data, the same marker size in pixels, drawn exactly.
size = np.sqrt(S) * DPI / 72
img = pointillist.points(
    {"x": x, "y": y, "value": value}, x="x", y="y", color="value", cmap="viridis",
    size=size, marker="circle", blend="alpha", width=PIXELS, height=PIXELS,
    x_range=RANGE, y_range=RANGE,
)
# Shown opaque: "alpha" blends the target's alpha channel too, and the figure's white would
# show through where an edge left it below 255.
right.set_box_aspect(1)
right.imshow(np.asarray(img)[..., :3], extent=img.extent, origin="upper",
             interpolation="nearest", aspect="auto")
right.set_xlim(RANGE)
right.set_ylim(RANGE)
right.set_title(f"pointillist.points(marker='circle', size={size:.2f} px)", fontsize=9)

out = sys.argv[1] if len(sys.argv) > 1 else "docs/images/markers_side_by_side.png"
fig.canvas.draw()
picture = np.asarray(fig.canvas.buffer_rgba())[..., :3]
try:
    from PIL import Image

    # 256 colours keep the file small; the markers' colours are the colormap's anyway.
    Image.fromarray(picture).quantize(256).save(out, optimize=True)
except ImportError:
    fig.savefig(out, dpi=DPI)
print(f"wrote {out}")
