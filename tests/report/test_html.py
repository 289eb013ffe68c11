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
    r = HtmlReport("t")
    r.figure(fig, caption='a "quoted" caption')
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


# ------------------------------------------------------------------ the page in a browser


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def browser_errors(path: Path, timeout: float = 60.0) -> list[str]:
    """Console errors, uncaught exceptions and failed loads of ``path`` in headless Chromium."""
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
    return errors


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
