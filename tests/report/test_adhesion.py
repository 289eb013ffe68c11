"""The creep-CoA figure of a test: ascending branches solid, descending dashed, the Polach fit
and its residuals in a second panel."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.adhesion import adhesion_figure


def test_adhesion_figure_with_branches_fit_and_residuals(analysed):
    rec = analysed.recording
    fig = adhesion_figure(
        rec["creep_smoothed"], rec["coa_corrected"], analysed.branches, analysed.fit, title="t"
    )
    top, residuals = fig.axes
    assert top.get_ylabel() == "coefficient of adhesion [-]"
    assert residuals.get_xlabel() == "creep [%]" and residuals.get_ylabel() == "residual [-]"
    entries = [t.get_text() for t in top.get_legend().get_texts()]
    assert entries[:2] == ["ascending", "descending"] and entries[2].startswith("Polach fit: μ0=")
    n = len(analysed.branches)
    assert n == 3
    styles = [ln.get_linestyle() for ln in top.get_lines()]
    assert styles[: 2 * n] == ["-", "--"] * n
    assert residuals.get_title().startswith("RMSE")
    np.testing.assert_allclose(residuals.get_lines()[0].get_ydata(), analysed.fit.residuals)
    assert fig.texts[0].get_text() == "t"
    plt.close(fig)


def test_adhesion_figure_without_branches_draws_all_points():
    s = np.linspace(0, 0.05, 50)
    fig = adhesion_figure(s, 0.4 * np.tanh(50 * s))
    (ax,) = fig.axes
    (line,) = ax.get_lines()
    assert line.get_label() == "measured" and line.get_xdata()[-1] == 5.0  # [%]
    assert ax.get_xlabel() == "creep [%]"
    plt.close(fig)


def test_creep_and_coa_of_different_lengths_are_a_parameter_error():
    import re

    import pytest

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("must be 1-D arrays of the same length")):
        adhesion_figure([0.1, 0.2, 0.3], [0.1, 0.2])
