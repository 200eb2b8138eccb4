"""Stability maps name their regions in words (eulersym stability ... --map ... --plot)."""

from __future__ import annotations

import numpy as np


def test_each_large_region_is_named_by_its_class_at_its_deepest_point():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from eulersym.model.stability_cli import _label_regions

    X, Y = np.meshgrid(np.linspace(0, 1, 50), np.linspace(0, 1, 40))
    classes = np.where(X > 0.6, 1, 0)
    classes[Y > 0.9] = -1                                   # a strip where the family has no member (10 %)
    classes[:2, :2] = 2                                     # a speck (0.2 %): too small to name
    fig, ax = plt.subplots()
    _label_regions(ax, X, Y, classes, ["no member", "unstable", "spectrally stable", "asymptotically stable"], None)
    texts = {t.get_text(): t.get_position() for t in ax.texts}
    plt.close(fig)
    assert set(texts) == {"no member", "unstable", "spectrally stable"}
    x, y = texts["spectrally stable"]
    assert 0.6 < x < 1 and y < 0.9                           # inside its region, away from the map's border
    x, y = texts["unstable"]
    assert x < 0.6 and 0.1 < y < 0.9
