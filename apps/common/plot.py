# The tools' figures, drawn by matplotlib from the panels fovbench and fovgen compute (plot.h):
#   python3 plot.py FIGURE.json
# FIGURE.json: {"outputs": ["a.png", "a.svg"], "panels": [{"title", "x_label", "y_label",
# "log_x", "log_y", "series": [{"name", "scheme", "style", "x", "y", "x_lo", "x_hi", "y_lo",
# "y_hi", "labels", "ringed", "lines", "markers"}]}]}. Embedded in the tools at build time
# and run by them; every output is written to a temporary name and renamed.
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402

# One colour per scheme in every figure (Okabe-Ito, safe for colour-blind readers).
SCHEME_COLOURS = {
    "nn": "#0072B2",
    "shepard": "#D55E00",
    "rbf": "#009E73",
    "barycentric": "#332288",
    "natural": "#117733",
    "uniform": "#CC79A7",
    "full": "#000000",
    "front-foveated": "#7F7F7F",
    "front-baseline": "#E69F00",
    # fovbench summary's schemes (a lower resolution is the uniform sets' colour)
    "sparse": "#56B4E9",
    "hybrid": "#882255",
    "falloff": "#44AA99",
    "lower-resolution": "#CC79A7",
    "goal": "#999933",
    "adaptive": "#AA4499",
}
OTHER_COLOURS = ["#56B4E9", "#882255", "#44AA99", "#999933", "#AA4499", "#F0E442"]
STYLES = {"solid": "-", "dashed": "--", "dotted": ":", "dashdot": "-."}
MARKERS = {"nn": "o", "shepard": "s", "rbf": "^", "barycentric": "v", "natural": "D", "uniform": "D", "full": "P", "adaptive": "*"}


def colour_of(scheme, others):
    if scheme in SCHEME_COLOURS:
        return SCHEME_COLOURS[scheme]
    if scheme not in others:
        others[scheme] = OTHER_COLOURS[len(others) % len(OTHER_COLOURS)]
    return others[scheme]


def plain(value, _pos=None):
    """Tick labels in one notation: plain decimals, never 5e-03 beside 0.02."""
    if value == 0:
        return "0"
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return text if abs(value) >= 1e-4 else f"{value:.1e}"


def overlaps(box, boxes):
    return any(box.overlaps(b) for b in boxes)


def place_labels(ax, fig, points):
    """Greedy placement: each label at the first offset whose box hits no other label, no
    marker and stays inside the axes; a leader line when it had to move far."""
    renderer = fig.canvas.get_renderer()
    axes_box = ax.get_window_extent(renderer)
    taken = []
    for x, y, _ in points:  # the markers themselves
        px, py = ax.transData.transform((x, y))
        taken.append(matplotlib.transforms.Bbox([[px - 5, py - 5], [px + 5, py + 5]]))
    near = [(6, 6), (6, -12), (-6, 6), (-6, -12), (0, 12), (0, -16), (10, -3), (-10, -3)]
    offsets = near + [(dx * 2.5, dy * 2.5) for dx, dy in near] + [(dx * 4, dy * 4) for dx, dy in near]
    for x, y, text in points:
        placed = None
        for dx, dy in offsets:
            ann = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=7,
                              ha="left" if dx >= 0 else "right", va="bottom" if dy >= 0 else "top",
                              arrowprops=dict(arrowstyle="-", lw=0.5, color="#555555") if abs(dx) > 12 or abs(dy) > 16 else None)
            box = ann.get_window_extent(renderer).expanded(1.05, 1.1)
            inside = axes_box.contains(box.x0, box.y0) and axes_box.contains(box.x1, box.y1)
            if inside and not overlaps(box, taken):
                placed = box
                break
            ann.remove()
        if placed is not None:
            taken.append(placed)


def draw_panel(ax, fig, panel, others):
    labelled = []
    for s in panel["series"]:
        colour = colour_of(s.get("scheme", s["name"]), others)
        style = STYLES.get(s.get("style", "solid"), "-") if s.get("lines", True) else "none"
        marker = MARKERS.get(s.get("scheme", ""), "o") if s.get("markers", True) else None
        x, y = s["x"], s["y"]
        if not x:
            continue
        xerr = yerr = None
        if s.get("x_lo") and s.get("x_hi"):
            xerr = [[max(v - lo, 0) for v, lo in zip(x, s["x_lo"])], [max(hi - v, 0) for v, hi in zip(x, s["x_hi"])]]
        if s.get("y_lo") and s.get("y_hi"):
            yerr = [[max(v - lo, 0) for v, lo in zip(y, s["y_lo"])], [max(hi - v, 0) for v, hi in zip(y, s["y_hi"])]]
        width = 2.0 if s.get("scheme", "").startswith("front-") else 1.2
        ax.errorbar(x, y, xerr=xerr, yerr=yerr, color=colour, linestyle=style, linewidth=width, marker=marker,
                    markersize=4.5, elinewidth=0.8, capsize=2, label=s["name"], zorder=3 if marker else 2)
        ringed = s.get("ringed") or []
        rx = [v for v, r in zip(x, ringed) if r]
        ry = [v for v, r in zip(y, ringed) if r]
        if rx:
            ax.scatter(rx, ry, s=90, facecolors="none", edgecolors=colour, linewidths=1.0, zorder=4)
        for xv, yv, text in zip(x, y, s.get("labels") or []):
            if text:
                labelled.append((xv, yv, text))
    ax.set_title(panel["title"], fontsize=10)
    ax.set_xlabel(panel["x_label"])
    ax.set_ylabel(panel["y_label"])
    for axis, log in ((ax.xaxis, panel.get("log_x")), (ax.yaxis, panel.get("log_y"))):
        if log:
            (ax.set_xscale if axis is ax.xaxis else ax.set_yscale)("log")
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_minor_formatter(NullFormatter())
        axis.set_major_formatter(FuncFormatter(plain))
    ax.grid(True, which="major", color="#DDDDDD", linewidth=0.6)
    ax.legend(fontsize=7, loc="best", framealpha=0.85)
    return labelled


def main(path):
    with open(path) as f:
        figure = json.load(f)
    panels = figure["panels"]
    fig, axes = plt.subplots(1, len(panels), figsize=(7.2 * len(panels), 4.8), squeeze=False)
    others = {}
    labelled = [draw_panel(ax, fig, panel, others) for ax, panel in zip(axes[0], panels)]
    fig.tight_layout()
    fig.canvas.draw()
    for ax, points in zip(axes[0], labelled):
        place_labels(ax, fig, points)
    for out in figure["outputs"]:
        root, ext = os.path.splitext(out)
        temp = f"{root}.tmp{os.getpid()}{ext}"
        fig.savefig(temp, dpi=100, format=ext.lstrip("."))
        os.replace(temp, out)


if __name__ == "__main__":
    main(sys.argv[1])
