"""Figures: provenance embedded in PNG, SVG and PDF; written atomically; closed."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pytest

from rollerrig.output import (
    OutputError,
    figure_provenance,
    provenance,
    run_context,
    save_figure,
)


def _figure():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    return fig


@pytest.mark.parametrize("suffix", [".png", ".svg", ".pdf"])
def test_provenance_is_embedded_and_read_back(tmp_path, suffix):
    with run_context(command=["rollerrig", "simulate"], drive="pmsm"):
        fig = _figure()
        path = save_figure(fig, tmp_path / f"f{suffix}", metadata={"note": "µ<&>(x)\\"})
    record = figure_provenance(path)
    assert record["software"] == "rollerrig"
    assert record["command"] == ["rollerrig", "simulate"]
    assert record["parameters"] == {"drive": "pmsm", "note": "µ<&>(x)\\"}
    assert not plt.fignum_exists(fig.number)  # closed
    assert [p.name for p in tmp_path.iterdir()] == [f"f{suffix}"]


def test_a_given_provenance_record_is_embedded_as_it_is(tmp_path):
    record = provenance(load_kn=50.0)
    path = save_figure(_figure(), tmp_path / "f.png", metadata=record)
    assert figure_provenance(path) == record


def test_png_text_chunk_is_readable_by_pillow(tmp_path):
    import json

    from PIL import Image

    path = save_figure(_figure(), tmp_path / "f.png")
    with Image.open(path) as im:
        assert im.text["Software"].startswith("rollerrig")
        assert json.loads(im.text["rollerrig_provenance"])["software"] == "rollerrig"


def test_a_format_without_metadata_is_refused_and_the_figure_closed(tmp_path):
    fig = _figure()
    with pytest.raises(OutputError, match=r"\.png, \.svg, \.pdf"):
        save_figure(fig, tmp_path / "f.jpg")
    assert not plt.fignum_exists(fig.number)
    assert list(tmp_path.iterdir()) == []


def test_a_failed_save_leaves_nothing(tmp_path):
    (tmp_path / "f.png").mkdir()
    with pytest.raises(OutputError, match="folder has this name"):
        save_figure(_figure(), tmp_path / "f.png")
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


@pytest.mark.parametrize("dpi", [0, -5, float("nan"), 1e7])
def test_a_dpi_out_of_range_is_a_parameter_error(tmp_path, dpi):
    import re

    from rollerrig._validation import ParameterError

    fig, _ = plt.subplots()
    with pytest.raises(ParameterError, match=re.escape("dpi must")):
        save_figure(fig, tmp_path / "f.png", dpi=dpi)
    assert not list(tmp_path.iterdir())


def test_no_figure_or_metadata_of_the_wrong_type_is_a_parameter_error(tmp_path):
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("fig must be a matplotlib Figure")):
        save_figure(None, tmp_path / "f.png")
    fig, _ = plt.subplots()
    with pytest.raises(ParameterError, match=re.escape("metadata must be a dict")):
        save_figure(fig, tmp_path / "f.png", metadata=[1])


def test_save_figure_refuses_a_path_that_is_not_one_and_closes_the_figure():
    """path=None had been a bare TypeError, raised before the figure was closed."""
    fig, _ = plt.subplots()
    with pytest.raises(OutputError, match="path must be a file path"):
        save_figure(fig, None)
    assert not plt.fignum_exists(fig.number)


@pytest.mark.parametrize("path", [None, 5, b"f.png"])
def test_reading_provenance_or_a_hash_refuses_a_path_that_is_not_one(path):
    from rollerrig._validation import ParameterError
    from rollerrig.output import file_sha256

    with pytest.raises(ParameterError, match="path must be a file path"):
        figure_provenance(path)
    with pytest.raises(ParameterError, match="path must be a file path"):
        file_sha256(path)
