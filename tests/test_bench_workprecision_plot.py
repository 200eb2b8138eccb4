"""The work-precision figure's layout and timing rule (``eulersym bench workprecision``), without running it."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402

from eulersym.bench import workprecision as wp  # noqa: E402


def _rows(problems, methods):
    rows = []
    for name in problems:
        for k, (method, route) in enumerate(methods):
            for j in range(3):
                rows.append(dict(problem=name, method=method, route=route, status="ok", time_s=10.0 ** (j - 3 + k / 5),
                                 error=10.0 ** (-3 * j - k), energy_drift=10.0 ** (-4 * j - k)))
    return rows


@pytest.mark.parametrize("problems", [("free_T100", "heavy_top"), ("heavy_top",), ("a", "b", "c", "d", "e", "f")])
def test_the_legend_overlaps_no_panel(tmp_path, monkeypatch, problems):
    """With any number of panels (``--only`` keeping two was the case that overlapped) the legend lies outside every
    panel of the saved figure."""
    import matplotlib.pyplot as plt

    figures = []
    monkeypatch.setattr(plt.Figure, "savefig", lambda self, *a, **k: figures.append((self, k)))
    methods = [("strang", "eulersym"), ("yoshida4", "numba"), ("DOP853", "lambdify"), ("Radau", "lambdify"),
               ("closed form", "eulersym"), ("dmv6", "numba")]
    assert wp._plot(_rows(problems, methods), str(tmp_path / "wp.png"))
    fig, kwargs = figures[-1]
    assert kwargs.get("bbox_inches") == "tight"  # the saved image grows to hold the legend
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    (legend,) = fig.legends
    box = legend.get_window_extent(renderer)
    assert len(legend.get_texts()) == len(methods)
    for ax in fig.axes:
        assert not box.overlaps(ax.get_tightbbox(renderer)), ax.get_title()
    assert fig.axes[0].get_ylabel() and "[s]" in fig.axes[-1].get_xlabel()


def test_the_warm_up_is_never_the_measurement():
    calls = []

    def run():
        calls.append(1)
        return len(calls)

    out, seconds = wp._timed(run, 1)
    assert len(calls) == 2 and out == 2 and seconds >= 0.0
    calls.clear()
    wp._timed(run, 3)
    assert len(calls) == 4
