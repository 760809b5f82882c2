"""The look of BeamContact's figures (study_report.py, render_stages.py), the same for every figure:
- PDF and PostScript with TrueType (Type 42) fonts, not Type 3 (which many journals refuse);
- PNG at 200 dpi;
- a style per series (colour, marker, line style) that does not repeat within a figure: the ten
  colours of matplotlib's "tab10" with seven markers (10 and 7 share no factor, so the first 70
  series have different colour-and-marker pairs) and four line styles (280 series), then colours
  of their own from a colour wheel.

Call `setup(matplotlib)` once before the first figure; `series_style(i)` is the i-th series' style."""
import colorsys

DPI = 200
COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X"]
LINESTYLES = ["-", "--", "-.", ":"]
DISTINCT = len(COLOURS) * len(MARKERS) * len(LINESTYLES)


def setup(matplotlib):
    matplotlib.rcParams.update({"pdf.fonttype": 42, "ps.fonttype": 42, "savefig.dpi": DPI, "figure.dpi": DPI})


def series_style(i):
    """The style of series i (0, 1, ...): a dict of color, marker and linestyle for plot()."""
    if i < DISTINCT:
        return {"color": COLOURS[i % len(COLOURS)], "marker": MARKERS[i % len(MARKERS)],
                "linestyle": LINESTYLES[(i // (len(COLOURS) * len(MARKERS))) % len(LINESTYLES)]}
    # Beyond: hues by the golden ratio (never the same twice), lightness and saturation varied.
    k = i - DISTINCT
    r, g, b = colorsys.hls_to_rgb((k * 0.6180339887498949) % 1.0, 0.35 + 0.1 * (k % 3), 0.75)
    return {"color": f"#{round(255 * r):02x}{round(255 * g):02x}{round(255 * b):02x}",
            "marker": MARKERS[k % len(MARKERS)], "linestyle": LINESTYLES[k % len(LINESTYLES)]}
