"""Matplotlib (Agg) helpers shared by the figures of reproduce-paper and evaluate."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def finish(ax, legend_size: int = 8, **legend: Any) -> None:
    """Grid and legend, the same on every panel (``legend``: more of matplotlib's legend arguments, e.g. its
    handles and where it sits)."""
    ax.grid(alpha=0.3)
    ax.legend(fontsize=legend_size, **legend)


def save(fig, path: Path, dpi: int = 120) -> Path:
    """Lay out, write and close a figure; returns its path."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
