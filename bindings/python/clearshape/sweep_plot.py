"""Summary plot of a sweep: the mean improvement (%) over two chosen axes (docs/sweeps.md).

Cells average every point with that pair of values (over the other axes and the draws);
failed points are left out. Numeric [random] axes are binned into `bins` equal intervals.
"""
import io
import math

import numpy as np


def _levels(values, bins):
    """The distinct values of a grid axis, or the bin centres of a random (continuous) one."""
    distinct = sorted(set(values))
    if len(distinct) <= bins or isinstance(values[0], str):
        return distinct, [distinct.index(v) for v in values]
    lo, hi = min(values), max(values)
    edges = np.linspace(lo, hi, bins + 1)
    idx = [min(bins - 1, int(np.searchsorted(edges, v, side="right") - 1)) for v in values]
    return [0.5 * (edges[i] + edges[i + 1]) for i in range(bins)], idx


def improvement_map(rows, x, y, bins=6):
    """(x_levels, y_levels, mean improvement [len(y), len(x)], point counts) from the result rows."""
    ok = [r for r in rows if r["status"] == "ok" and not math.isnan(r["improvement_percent"])]
    if not ok:
        raise ValueError("no successful points to plot")
    xl, xi = _levels([r[x] for r in ok], bins)
    yl, yi = _levels([r[y] for r in ok], bins)
    total = np.zeros((len(yl), len(xl)))
    count = np.zeros((len(yl), len(xl)), dtype=int)
    for r, i, j in zip(ok, xi, yi):
        total[j, i] += r["improvement_percent"]
        count[j, i] += 1
    with np.errstate(invalid="ignore"):
        mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    return xl, yl, mean, count


def plot_png(rows, x, y, title):
    """The map as PNG bytes (matplotlib, Agg; no date in the metadata)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xl, yl, mean, _ = improvement_map(rows, x, y)
    fig, ax = plt.subplots(figsize=(1.2 + 0.9 * len(xl), 1.0 + 0.6 * len(yl)), dpi=100)
    im = ax.imshow(mean, origin="lower", cmap="viridis", aspect="auto")
    fmt = lambda v: v if isinstance(v, str) else f"{v:.4g}"  # noqa: E731
    ax.set_xticks(range(len(xl)), [fmt(v) for v in xl])
    ax.set_yticks(range(len(yl)), [fmt(v) for v in yl])
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    for j in range(len(yl)):
        for i in range(len(xl)):
            if not np.isnan(mean[j, i]):
                ax.text(i, j, f"{mean[j, i]:.0f}", ha="center", va="center", color="white", fontsize=8)
    fig.colorbar(im, ax=ax, label="improvement of Eq. 5.1 MD (%)")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()
