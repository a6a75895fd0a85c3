"""What every plot shares: matplotlib's pyplot on the Agg backend (no display needed), and saving a figure."""

from __future__ import annotations

from pathlib import Path


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, png) -> Path:
    png = Path(png)
    fig.tight_layout()
    fig.savefig(png)
    fig.clf()
    pyplot().close(fig)
    return png
