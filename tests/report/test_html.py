"""The HTML report is self-contained (no external scripts, styles, fonts or images: figures are
data: URIs) and opens in a headless browser without console errors.

The self-containment check parses the HTML and always runs. The browser check drives headless
Chromium over its DevTools pipe (``--remote-debugging-pipe``: JSON messages on file descriptors
3 and 4, standard library only) and collects console errors, uncaught exceptions and failed
loads; it is skipped, saying why, when no ``chromium`` or ``chromium-browser`` is installed.
Both checks are first shown to fail on a page that breaks the rules.
"""

from __future__ import annotations

import base64
import json
import os
import re
import select
import shutil
import subprocess
import tempfile
import time
from html.parser import HTMLParser
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollerrig.report.html import HtmlReport

_URL_ATTRIBUTES = {"src", "href", "srcset", "poster", "data", "action", "formaction", "background"}

BAD_PAGE = """<!DOCTYPE html><html><head><meta charset="utf-8"><title>bad</title>
<link rel="stylesheet" href="https://example.org/x.css">
<style>@import url("http://example.org/y.css"); body { font-family: web; }
@font-face { font-family: web; src: url(https://example.org/f.woff2); }</style>
<script src="https://example.org/x.js"></script></head>
<body><img src="missing-figure.png"><script>console.error("boom"); notDefined();</script>
</body></html>
"""


class _Refs(HTMLParser):
    """Every tag, URL-valued attribute and inline style/script text of a page."""

    def __init__(self):
        super().__init__()
        self.tags: list[str] = []
        self.urls: list[tuple[str, str, str]] = []
        self.styles: list[str] = []
        self.scripts: list[str] = []
        self._in: str | None = None

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self._in = tag if tag in ("style", "script") else None
        for key, value in attrs:
            if key in _URL_ATTRIBUTES and value is not None:
                self.urls.append((tag, key, value))
            if key == "style" and value:
                self.styles.append(value)

    def handle_data(self, data):
        if self._in == "style":
            self.styles.append(data)
        elif self._in == "script":
            self.scripts.append(data)

    def handle_endtag(self, tag):
        self._in = None


_FOREIGN_TAGS = ("script", "link", "iframe", "object", "embed", "base", "frame")
"""Elements a static report never needs (a script, even inline, would be a new dependency)."""


def external_references(html: str) -> list[str]:
    """What makes a page depend on anything outside itself (empty for a self-contained one)."""
    refs = _Refs()
    refs.feed(html)
    refs.close()
    found = [f"<{t}> element" for t in refs.tags if t in _FOREIGN_TAGS]
    for tag, key, value in refs.urls:
        if not value.startswith("data:"):
            found.append(f'<{tag} {key}="{value[:60]}">')
    for css in refs.styles:
        found += [f"CSS {m}" for m in re.findall(r"@import|@font-face|url\s*\(", css)]
    text = " ".join([*refs.styles, *(v for _, _, v in refs.urls)])
    found += [f"http(s) URL {m}" for m in re.findall(r"https?://[^\s\"'<>)]+", text)]
    return found


def test_the_self_containment_check_finds_external_references():
    found = " | ".join(external_references(BAD_PAGE))
    expected = [
        "<link> element",
        "<script> element",
        "CSS @import",
        "CSS @font-face",
        '<img src="missing-figure.png">',
        "http(s) URL https://example.org/x.css",
    ]
    for what in expected:
        assert what in found, what


def test_the_written_report_is_self_contained(written):
    html = written[2].read_text(encoding="utf-8")
    assert external_references(html) == []
    assert html.startswith("<!DOCTYPE html>") and "<meta charset='utf-8'>" in html
    images = re.findall(r'<img [^>]*src="([^"]+)"', html)
    assert len(images) >= 5
    for src in images:
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"


def test_text_is_escaped_and_nan_shown_as_na():
    r = HtmlReport("<b>T&C</b>")
    r.paragraph("<script>alert(1)</script>", note=True)
    r.table(["a [N]", "b", "c"], [[float("nan"), np.float64(np.inf), None], [1.5, "[kN]", 2]])
    text = r.render()
    assert "<script>" not in text and "&lt;script&gt;" in text
    assert "<title>&lt;b&gt;T&amp;C&lt;/b&gt;</title>" in text
    assert "nan" not in text.lower().replace("n/a", "") and "inf" not in text
    assert text.count("n/a") == 2 and "[kN]" in text and "<th>a [N]</th>" in text
    assert '<p class="note">' in text


def test_figures_are_embedded_and_closed():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    ax.set_ylabel("power [(N.m)²]")
    r = HtmlReport("t")
    r.figure(fig, caption='a "quoted" caption')
    assert ax.get_ylabel() == "power [(N·m)²]"  # typeset as every saved figure
    assert not plt.fignum_exists(fig.number)
    (part,) = r.parts
    assert part.startswith(
        '<figure><img alt="a &quot;quoted&quot; caption" src="data:image/png;base64,'
    )
    assert "<figcaption>a &quot;quoted&quot; caption</figcaption>" in part


def test_write_gives_the_rendered_page_and_provenance(tmp_path):
    r = HtmlReport("t")
    r.provenance({"software": "rollerrig", "x": "<y>"})
    path = r.write(tmp_path / "r.html")
    text = path.read_text(encoding="utf-8")
    assert text == r.render()
    assert "<h2>Provenance</h2>" in text and "&lt;y&gt;" in text


def test_tables_typeset_units_numbers_and_symbols():
    r = HtmlReport("t")
    r.table(
        ["input", "symbol", "J [kg.m^2]", "CoA [-]", "lag [s]", "unit"],
        [["roller inertia", "W_d", 45.0, 0.1234567, 7.748e-06, "N.m"],
         ["rig CoA", "e_res,s", 2.6390000000000002, -0.0, "3.3e-14", "kg.m^2"]],
        math_columns=(1,),
    )  # fmt: skip
    text = r.render()
    assert '<div class="table"><table>' in text  # its own box, which scrolls (the CSS)
    assert ".table { max-width: 100%; overflow-x: auto;" in text
    assert '<th class="n">J [kg·m²]</th>' in text and '<th class="n">CoA</th>' in text
    assert "<td>W<sub>d</sub></td>" in text and "<td>e<sub>res,s</sub></td>" in text
    assert '<td class="n">7.748 × 10⁻⁶</td>' in text and '<td class="n">3.3 × 10⁻¹⁴</td>' in text
    assert '<td class="n">2.639</td>' in text and '<td class="n">0</td>' in text
    assert "<td>N·m</td>" in text and "<td>kg·m²</td>" in text
    assert "e-06" not in text and "[-]" not in text and "-0<" not in text


def test_paragraphs_are_typeset_and_formulas_get_subscripts():
    r = HtmlReport("t")
    r.paragraph("mu0 of 0.3 x the peak, 3 N.m, J^T J singular (8.68e+32), file a_b.csv")
    r.paragraph("F_x r_r = T56 + J5 (α5 + e_α), |c_i| u(x_i)", math=True)
    plain, formula = r.parts
    assert plain == ("<p>μ0 of 0.3 × the peak, 3 N·m, JᵀJ singular (8.68 × 10³²), file a_b.csv</p>")
    assert formula == (
        "<p>F<sub>x</sub> r<sub>r</sub> = T56 + J5 (α5 + e<sub>α</sub>), "
        "|c<sub>i</sub>| u(x<sub>i</sub>)</p>"
    )


def test_provenance_paths_are_relative_to_the_report(tmp_path):
    out = tmp_path / "run"
    r = HtmlReport("t")
    r.provenance(
        {"command": ["rollerrig", "demo", "--out", str(out)],
         "inputs": {"recording": {"path": str(out / "a.tdms")},
                    "rig": {"path": str(tmp_path / "rigs" / "r.toml")}}},
        relative_to=out,
    )  # fmt: skip
    text = r.render()
    assert str(tmp_path) not in text
    assert "&quot;a.tdms&quot;" in text and "&quot;../rigs/r.toml&quot;" in text
    assert "&quot;--out&quot;,\n    &quot;.&quot;" in text


# ------------------------------------------------------------------ the page in a browser


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def browser_errors(path: Path, timeout: float = 60.0) -> list[str]:
    """Console errors, uncaught exceptions and failed loads of ``path`` in headless Chromium."""
    return _in_chromium(path, timeout)[0]


_WIDTHS_JS = """(() => {
  const page = document.documentElement.scrollWidth;
  const boxes = [...document.querySelectorAll('body > *')]
    .filter(e => e.getBoundingClientRect().right > window.innerWidth + 0.5)
    .map(e => e.tagName + '.' + e.className);
  const tables = [...document.querySelectorAll('div.table')]
    .filter(d => d.scrollWidth > d.clientWidth + 0.5).length;
  return JSON.stringify({page, window: window.innerWidth, beyond: boxes, scrolling: tables});
})()"""


def page_widths(path: Path, widths=(1100, 1400), timeout: float = 60.0) -> dict[int, dict]:
    """What overflows ``path`` at each window width [CSS px]: the document's scroll width
    (``page``), the window's (``window``), top-level elements reaching past the window
    (``beyond``) and the count of tables that scroll inside their box (``scrolling``)."""
    return _in_chromium(path, timeout, widths)[1]


def _in_chromium(path: Path, timeout: float = 60.0, widths=()) -> tuple[list[str], dict]:
    """Load ``path`` in headless Chromium over its DevTools pipe: (errors, measured widths)."""
    to_r, to_w = os.pipe()  # we write commands, Chromium reads them on fd 3
    from_r, from_w = os.pipe()  # Chromium writes replies and events on fd 4

    def as_fds_3_and_4():
        a, b = os.dup(to_r), os.dup(from_w)
        os.dup2(a, 3)
        os.dup2(b, 4)

    profile = tempfile.mkdtemp(prefix="rollerrig-chromium-")
    log = tempfile.TemporaryFile()
    proc = subprocess.Popen(
        [_chromium(), "--headless", "--disable-gpu", "--no-sandbox", "--no-first-run",
         "--remote-debugging-pipe", f"--user-data-dir={profile}", "about:blank"],
        preexec_fn=as_fds_3_and_4, pass_fds=(3, 4), stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL, stderr=log,
    )  # fmt: skip
    os.close(to_r)
    os.close(from_w)
    deadline = time.monotonic() + timeout
    events: list[dict] = []
    measured: dict[int, dict] = {}
    pending = b""
    counter = 0

    def receive(until):
        nonlocal pending
        while True:
            while b"\0" in pending:
                raw, pending = pending.split(b"\0", 1)
                message = json.loads(raw)
                events.append(message)
                if until(message):
                    return message
            left = deadline - time.monotonic()
            ready = select.select([from_r], [], [], max(left, 0.0))[0] if left > 0 else []
            chunk = os.read(from_r, 1 << 16) if ready else b""
            if not chunk:
                log.seek(0)
                tail = log.read().decode(errors="replace")[-2000:]
                raise AssertionError(f"no answer from Chromium (timeout or exit); stderr:\n{tail}")
            pending += chunk

    def call(method, params=None, session=None):
        nonlocal counter
        counter += 1
        message = {"id": counter, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(to_w, json.dumps(message).encode() + b"\0")
        reply = receive(lambda m, i=counter: m.get("id") == i)
        assert "error" not in reply, reply
        return reply["result"]

    try:
        target = call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page"):
            call(f"{domain}.enable", session=session)
        call("Page.navigate", {"url": path.resolve().as_uri()}, session=session)
        if not any(e.get("method") == "Page.loadEventFired" for e in events):
            receive(lambda m: m.get("method") == "Page.loadEventFired")
        for width in widths:
            call("Emulation.setDeviceMetricsOverride",
                 {"width": width, "height": 900, "deviceScaleFactor": 1, "mobile": False},
                 session=session)  # fmt: skip
            value = call("Runtime.evaluate", {"expression": _WIDTHS_JS}, session=session)
            measured[width] = json.loads(value["result"]["value"])
        deadline = min(deadline, time.monotonic() + 0.5)  # late messages
        try:
            receive(lambda m: False)
        except AssertionError:
            pass
        try:
            call("Browser.close")
        except AssertionError:
            pass
    finally:
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        os.close(to_w)
        os.close(from_r)
        log.close()
        shutil.rmtree(profile, ignore_errors=True)
    errors = []
    for event in events:
        method, p = event.get("method"), event.get("params", {})
        if method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            args = " ".join(str(a.get("value", a.get("description", ""))) for a in p["args"])
            errors.append(f"console.{p['type']}: {args}")
        elif method == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            errors.append("exception: " + d.get("exception", {}).get("description", d["text"]))
        elif method == "Log.entryAdded" and p["entry"]["level"] == "error":
            errors.append(f"{p['entry']['text']} {p['entry'].get('url', '')}".strip())
    return errors, measured


needs_chromium = pytest.mark.skipif(
    _chromium() is None,
    reason="no chromium or chromium-browser on PATH (install it, e.g. apt-get install chromium, "
    "to check that the report opens without console errors)",
)


@needs_chromium
def test_the_browser_check_sees_console_errors_exceptions_and_failed_loads(tmp_path):
    page = tmp_path / "bad.html"
    page.write_text(BAD_PAGE, encoding="utf-8")
    errors = " | ".join(browser_errors(page))
    assert "console.error: boom" in errors
    assert "notDefined is not defined" in errors
    assert "missing-figure.png" in errors  # the failed load of a figure that is not embedded


@needs_chromium
def test_the_report_opens_in_headless_chromium_without_console_errors(written):
    assert browser_errors(written[2]) == []


@needs_chromium
def test_the_page_never_scrolls_sideways_wide_tables_scroll_in_their_box(written, tmp_path):
    wide = HtmlReport("wide")
    wide.table([f"column {i} [N.m]" for i in range(40)], [[1234.5678] * 40] * 3)
    pages = [wide.write(tmp_path / "wide.html"), written[2]]
    for page in pages:
        for width, m in page_widths(page, (1100, 1400)).items():
            assert m["page"] <= m["window"] and m["beyond"] == [], (page.name, width, m)
    # the 40-column table is wider than the column, and scrolls inside its own box
    assert all(m["scrolling"] == 1 for m in page_widths(pages[0], (1100, 1400)).values())


# --------------------------------------------------------------------------------------------
# Arguments of the wrong kind: one clear error, the figure left to the caller
# --------------------------------------------------------------------------------------------


def test_a_figure_of_none_is_refused():
    """None had been a bare AttributeError ('NoneType' object has no attribute 'texts')."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match="fig must be a matplotlib Figure, got None"):
        HtmlReport("t").figure(None)


@pytest.mark.parametrize(
    ("dpi", "message"),
    [
        (0, r"dpi must lie in \[1, 10000\] \[dots per inch\], got 0"),
        (-5, r"dpi must lie in \[1, 10000\]"),
        (float("nan"), "dpi must be finite"),
        ("text", "dpi must be a number"),
        (True, "dpi must be a number"),
        ([100, 200], "dpi must be a single number"),
        (1e9, r"dpi must lie in \[1, 10000\]"),
    ],
)
def test_a_wrong_dpi_is_refused_before_drawing_and_the_figure_kept(dpi, message):
    """0 and -5 had been matplotlib's ValueError, NaN "cannot convert float NaN to integer",
    text a bare TypeError, True a FreeType error; nothing was added to the report."""
    from rollerrig._validation import ParameterError

    report = HtmlReport("t")
    fig, _ = plt.subplots()
    try:
        with pytest.raises(ParameterError, match=message):
            report.figure(fig, "caption", dpi=dpi)
        assert plt.fignum_exists(fig.number) and report.parts == []
        report.figure(fig, "caption", dpi=50)  # the caller may draw it again
        assert len(report.parts) == 1 and not plt.fignum_exists(fig.number)
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda r: r.figure(plt.figure(), caption=5), "caption must be a str"),
        (lambda r: r.heading(None), "heading: text must be a str, got None"),
        (lambda r: r.paragraph(3.5), "paragraph: text must be a str"),
        (lambda r: r.table("ab", [[1, 2]]), "header must be a list of column titles"),
        (lambda r: r.table(["a"], "xy"), "rows must be a list of rows"),
        (lambda r: r.table(["a", "b"], [1, 2]), r"rows\[0\] must be a list of cells"),
        (lambda r: r.table(["a", "b"], [[1, 2, 3]]), r"rows\[0\] has 3 cells for 2 columns"),
        (lambda r: r.table(["a"], [[1.5]], digits=0), r"digits must be a whole number in \[1"),
        (lambda r: r.table(["a"], [["x"]], math_columns=5), "math_columns must be a list"),
        (lambda r: r.provenance(None), "record must be a dict"),
        (lambda r: r.provenance({}, relative_to=5), "relative_to must be a folder"),
    ],
)
def test_report_arguments_of_the_wrong_kind_are_refused(call, message):
    """Each had been a bare AttributeError or TypeError, or a silent wrong page (a str of rows
    as one-letter rows, a row longer than the header, None written as "None")."""
    from rollerrig._validation import ParameterError

    report = HtmlReport("t")
    try:
        with pytest.raises(ParameterError, match=message):
            call(report)
    finally:
        plt.close("all")
    assert report.parts == []
    with pytest.raises(ParameterError, match="title must be a str"):
        HtmlReport(None)
