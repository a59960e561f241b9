"""The report's fragility figures show all their words: nothing cut at the edges, no layout warning (issue 38, item 4).

Before, `frustum report ... --reference stack` of the seven models of `studies/drums_vs_rigid/paper.toml`
printed "constrained_layout not applied" and its `fragility_overturning.png` had its title (the models'
line key, one line wider than the figure) and its legend (inside the axes, a marker key longer than
the figure) cut off at the right edge.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np
import pytest
from fragility_synthetic import make_results

from pipeline import fragility as F
from pipeline.plotting_fragility import fragility_figure
from pipeline.report import write_report

#: The models of the drums_vs_rigid paper study and the peer engine it is compared with.
SEVEN = ("rigid", "monolith", "stack", "stack-narrow", "stack-wide", "stack-half-step", "pybullet")
BASES = ("3d", "3d-compliant", "3d-compliant", "3d-compliant", "3d-compliant", "3d-compliant", "pybullet")
#: A title as long as the report's former one (the line key of seven models), to be wrapped.
LONG_TITLE = ("Probability of overturning, column 'paper': RIGID (dash-dotted), MONOLITH (densely dotted), STACK "
              "(densely dashed), STACK-NARROW (dash-dot-dotted), STACK-WIDE (dash-dotted), STACK-HALF-STEP "
              "(densely dotted) and PYBULLET (dotted)")


def _results(models):
    ds, _ = make_results(models=models, columns=("paper",), n_records=8, angles=(0.0,),
                         scales=(0.2, 0.4, 0.6, 0.8, 1.0, 1.5), seed=4)
    if models == SEVEN:  # as a study with variants writes it (a peer engine's model the registry does not know)
        ds["base_model"] = ("model", np.array(BASES, dtype=object))
    return ds


def _texts(fig):
    """The figure's words a reader must see: title, legend (title and entries), axis labels."""
    legend = fig.legends[0] if fig.legends else fig.axes[0].get_legend()
    texts = [fig._suptitle, legend.get_title(), *legend.get_texts()]
    for ax in fig.axes:
        for one in (ax, *ax.child_axes):  # the top axis (m/s2) is a child of the axes
            texts += [one.xaxis.label, one.yaxis.label]
    return [t for t in texts if t is not None and t.get_visible() and t.get_text()]


@pytest.fixture(scope="module")
def frags():
    """Fragility of one model and of seven, with bootstrap bands (their note lengthens the title)."""
    return {models: F.fragility(_results(models), im="pga", bootstrap=5, seed=1) for models in (("3d",), SEVEN)}


def _drawn_whole(draw):
    """Draw the figure ``draw()`` makes; assert no warning and every word inside it, legend off the axes."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fig = draw()
        fig.canvas.draw()  # constrained layout runs here, and warns here when it gives up
    assert [str(w.message) for w in caught] == []
    renderer = fig.canvas.get_renderer()
    inside = fig.bbox
    texts = _texts(fig)
    for text in texts:
        box = text.get_window_extent(renderer)
        # 0.5 px: the extents are floats rounded to pixels by the renderer
        assert (box.x0 >= inside.x0 - 0.5 and box.x1 <= inside.x1 + 0.5
                and box.y0 >= inside.y0 - 0.5 and box.y1 <= inside.y1 + 0.5), (text.get_text()[:60], box, inside)
    legend = fig.legends[0] if fig.legends else fig.axes[0].get_legend()
    assert not legend.get_window_extent(renderer).overlaps(fig.axes[0].get_window_extent(renderer))  # not over curves
    plt.close(fig)
    return texts


@pytest.mark.parametrize("models, states, title", [
    (("3d",), None, None),  # one model, every damage state (the report's fragility_states figure)
    (SEVEN, ["overturning"], LONG_TITLE),  # seven models, overturning, the report's former title
    (SEVEN, None, None),  # the crowded case: seven models times four states
])
def test_every_word_of_the_fragility_figure_lies_inside_it(frags, models, states, title):
    texts = _drawn_whole(lambda: fragility_figure(frags[models], states=states, title=title))
    n_states = 1 if states else frags[models].sizes["state"]
    # the premise: title, legend title, one entry per model and state, 3 axis labels (the top one in m/s2)
    assert len(texts) == 2 + len(models) * n_states + 3


class _Drawn(Exception):
    """Stops a report once it has asked for its overturning figure."""


def test_the_report_with_a_reference_draws_its_overturning_figure_whole(monkeypatch, tmp_path):
    import pipeline.report

    asked = []

    def plot_fragility(frag, stem, **kwargs):
        asked.append((frag, stem, kwargs))
        raise _Drawn

    monkeypatch.setattr(pipeline.report.P, "plot_fragility", plot_fragility)
    with pytest.raises(_Drawn):  # the rest of the report (its HTML alone takes 20 s) is not this test's
        write_report(_results(SEVEN), tmp_path / "r", bootstrap=5, reference="stack")
    frag, stem, kwargs = asked[0]
    assert stem.endswith("fragility_overturning") and kwargs["states"] == ["overturning"]
    _drawn_whole(lambda: fragility_figure(frag, **kwargs))
