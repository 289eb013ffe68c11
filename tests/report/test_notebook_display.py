"""Notebook manners (issue 23, point 8): a short ``repr`` and a small, escaped ``_repr_html_``
for recordings, analyses, rigs and calibrations; ``help(rollerrig)`` without importing
everything."""

from __future__ import annotations

import html
import io
import subprocess
import sys
from contextlib import redirect_stdout

import numpy as np

from rollerrig._display import MAX_ROWS, fmt, html_table
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig

MAX_REPR_LINES = 8
MAX_REPR_CHARS = 1500


def _short(text: str) -> None:
    assert len(text.splitlines()) <= MAX_REPR_LINES, text
    assert len(text) <= MAX_REPR_CHARS, len(text)


def _html(text: str) -> None:
    assert text.startswith("<div>") and text.endswith("</div>"), text[:80]
    assert text.count("<tr>") <= MAX_ROWS + 2
    assert "<script" not in text


def test_recording_repr_is_a_few_lines_and_names_rate_channels_units():
    t = np.arange(10_000) / 250.0
    rec = Recording(
        t,
        {f"ch{i}": np.sin(t + i) for i in range(30)},
        {f"ch{i}": "N.m" for i in range(30)},
        {"source": "/home/someone/data/run <1>.tdms", "format": "tdms"},
    )
    text = repr(rec)
    _short(text)
    assert text.startswith("Recording: 10000 samples at 250 Hz, 40 s")
    assert "ch0 [N.m]" in text and "(+24 more)" in text
    assert "run <1>.tdms (tdms)" in text and "/home/someone" not in text
    page = rec._repr_html_()
    _html(page)
    assert "run &lt;1&gt;.tdms" in page and "run <1>" not in page
    assert "6 more rows" in page  # 30 channels, 24 shown


def test_analysis_repr_is_short_and_says_the_fits(analysed):
    text = repr(analysed)
    _short(text)
    assert text.startswith("TestAnalysis of ")
    assert "Polach fit, corrected CoA: μ0" in text and "RMS" in text
    assert "every result: .summary()" in text
    _html(analysed._repr_html_())
    assert "μ0" in analysed._repr_html_()


def test_rig_repr_names_the_chain_in_typeset_units():
    rig = default_rig()
    text = repr(rig)
    _short(text)
    assert text.startswith(f"RigParameters {rig.meta.name!r}")
    assert "inertia [kg·m²]: " in text and "roller 45" in text
    assert "stiffness [N·m/rad]: " in text and "roller_shaft 4.35e+04" in text
    page = rig._repr_html_()
    _html(page)
    assert "inertia.roller" in page and "kg·m²" in page
    # the repr of a variant differs where its value does
    assert "roller_shaft 5e+04" in repr(rig.with_overrides({"stiffness.roller_shaft": 5e4}))


def test_calibration_repr_says_validity_values_and_residuals():
    from rollerrig.calibrate.result import Calibration, ChannelFit, FittedParameter
    from rollerrig.contact.creep import POLACH_DRY

    rig = default_rig()
    params = {
        "stiffness.roller_shaft": FittedParameter(
            "stiffness.roller_shaft", "N.m/rad", 43500.0, 47850.0, 1.7, 1.5, True
        ),
        "damping.wheel_shaft": FittedParameter(
            "damping.wheel_shaft", "N.m.s/rad", 10.0, None, None, None, False, "se 3.2 > 0.5 <x>"
        ),
    }
    channel = ChannelFit("t56", "N.m", 100, 1.0, "sensor", 1.0, 3.4213, 0.4321, {})
    cal = Calibration(
        parameters=params,
        nuisance={},
        keys=("stiffness.roller_shaft",),
        covariance=np.eye(1),
        correlation=np.eye(1),
        channels={"t56": channel},
        rig=rig,
        friction=POLACH_DRY,
        warnings=["damping.wheel_shaft: not identified"],
        notes=[],
        experiment={},
        fit={},
        recording={"source": "/somewhere/seed-30kmh-dry.tdms"},
        series={},
    )
    text = repr(cal)
    _short(text)
    assert text.startswith("Calibration to seed-30kmh-dry.tdms (valid; roller drive induction")
    assert "stiffness.roller_shaft: 4.785e+04 ± 1.7 N·m/rad (start 4.35e+04)" in text
    assert "damping.wheel_shaft: not identified (se 3.2 > 0.5 <x>)" in text
    assert "residual RMS, t56: 3.42 -> 0.432 N·m" in text
    page = cal._repr_html_()
    _html(page)
    assert "&lt;x&gt;" in page and "<x>" not in page


def test_html_table_escapes_every_cell_and_counts_what_it_leaves_out():
    rows = [(f"<k{i}>", "a & b") for i in range(MAX_ROWS + 3)]
    page = html_table("<title>", rows, header=("<key>", "value"), note="<note>")
    assert "<title>" not in page and "&lt;title&gt;" in page
    assert "&lt;key&gt;" in page and "&lt;note&gt;" in page
    assert page.count("a &amp; b") == MAX_ROWS and "3 more rows" in page
    assert html.unescape("&lt;k0&gt;") == "<k0>"
    assert fmt(2.6390000000000002) == "2.639" and fmt(float("nan")) == "—"


def test_help_of_the_package_is_fast_and_imports_no_subpackage():
    code = (
        "import io, sys, contextlib, rollerrig\n"
        "buf = io.StringIO()\n"
        "with contextlib.redirect_stdout(buf):\n"
        "    help(rollerrig)\n"
        "text = buf.getvalue()\n"
        "heavy = [m for m in ('rollerrig.measure', 'rollerrig.solve', 'scipy', 'xarray') "
        "if m in sys.modules]\n"
        "print(len(text.splitlines()), heavy)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    ).stdout.split(maxsplit=1)
    assert int(out[0]) < 150, out
    assert out[1].strip() == "[]", out


def test_help_lists_every_top_level_name_and_they_still_load():
    import rollerrig

    buf = io.StringIO()
    with redirect_stdout(buf):
        help(rollerrig)
    text = buf.getvalue()
    for name in rollerrig._EXPORTS:
        assert f"``{name}``" in text, name
    assert rollerrig.default_rig().meta.name  # attribute access outside pydoc still loads
