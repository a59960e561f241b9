"""Issue 26: every file the project writes besides its netCDF results carries a mark a rerun recognises.

:func:`pipeline.figfile.save_figure` marks a figure in its format's metadata,
:func:`pipeline.paths.written_by_frustum` finds the mark reading only the two
ends of a file, and :func:`pipeline.paths.check_output_file` replaces an
existing file only if it carries the mark.
"""

import os

import pytest

from pipeline.errors import InputError
from pipeline.paths import MARK, MARK_WINDOW, check_output_file, check_plot_file, mark_text, written_by_frustum


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.5, 1.0))
    ax.plot([0, 1], [1, 0])
    return fig


# pgf needs a TeX installation; raw and rgba are bare pixels: no place for a mark
MARKABLE = ["png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "gif", "avif"]


@pytest.mark.parametrize("fmt", MARKABLE + ["raw"])
def test_every_figure_format_that_can_carry_the_mark_carries_it(tmp_path, fmt):
    from pipeline.figfile import save_figure

    path = tmp_path / f"fig.{fmt}"
    try:
        save_figure(_figure(), path, dpi=30)
    except (OSError, KeyError, ValueError) as exc:  # a Pillow built without this codec (avif)
        pytest.skip(f"{fmt}: {exc}")
    assert written_by_frustum(path) is (fmt != "raw")
    if fmt != "raw":
        assert check_plot_file(path, "--plot") == str(path)  # a rerun may replace it
    else:  # a format that cannot carry the mark: an existing file is never replaced
        with pytest.raises(InputError, match="exists and was not written by frustum"):
            check_plot_file(path, "--plot")


def test_the_mark_is_found_at_either_end_of_a_large_file_and_nowhere_else(tmp_path):
    big = tmp_path / "big.pdf"
    try:
        with open(big, "wb") as fh:  # sparse: 8 GiB, of which only the two ends are read
            fh.truncate(8 << 30)
    except OSError as exc:
        pytest.skip(f"no sparse 8 GiB file here: {exc}")
    assert not written_by_frustum(big)
    with open(big, "r+b") as fh:
        fh.seek((4 << 30))  # in the middle, as a PDF's page content might quote it: not looked at
        fh.write(MARK.encode())
    assert not written_by_frustum(big)
    with open(big, "r+b") as fh:
        fh.seek((8 << 30) - MARK_WINDOW // 2)
        fh.write(mark_text().encode())
    assert written_by_frustum(big)
    small = tmp_path / "small.png"
    small.write_bytes(b"\x89PNG" + b"\0" * (MARK_WINDOW - 10) + MARK.encode() + b"\0" * 10)  # across the head's end
    assert written_by_frustum(small)
    assert not written_by_frustum(tmp_path / "missing.png")


def test_a_users_file_is_refused_and_left_as_it_was(tmp_path):
    photo = tmp_path / "site.png"
    photo.write_bytes(b"\x89PNG\r\n\x1a\n my photo")
    for kind in ("marked", "histories", "risk-csv"):
        with pytest.raises(InputError) as err:
            check_output_file(photo, "--plot", kind=kind)
        assert str(err.value).startswith(f"--plot {str(photo)!r} exists and ")
        assert str(err.value).endswith("give another file name or remove it")
    assert photo.read_bytes() == b"\x89PNG\r\n\x1a\n my photo"
    assert check_output_file(photo, "--log", kind=None) == str(photo)  # a log is appended to, not replaced
    assert check_output_file(tmp_path / "new.png", "--plot") == str(tmp_path / "new.png")


def test_the_writers_replace_a_file_they_own_even_unmarked(tmp_path):
    """The study scripts regenerate figures committed before the mark (``studies/*/figures``)."""
    from pipeline.figfile import save_figure

    old = tmp_path / "figures" / "fragility_overturning.png"
    old.parent.mkdir()
    old.write_bytes(b"\x89PNG\r\n\x1a\n written before the mark")
    save_figure(_figure(), old, dpi=30)
    assert written_by_frustum(old) and os.listdir(old.parent) == ["fragility_overturning.png"]
