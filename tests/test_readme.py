"""The README's notebook block runs as written (the contract: README commands stay true)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def _notebook_block() -> str:
    text = README.read_text(encoding="utf-8")
    section = text.split("## In a notebook", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert len(blocks) == 1, "the notebook section holds one python block"
    return blocks[0]


@pytest.mark.slow
def test_notebook_block_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "readme"}
    exec(compile(_notebook_block(), str(README), "exec"), namespace)
    printed = capsys.readouterr().out
    assert "ramp" in printed  # the analysis found the ramps of the simulated protocol
    assert (tmp_path / "two-releases.tdms").is_file()
    written = sorted(p.name for p in (tmp_path / "notebook-output").iterdir())
    assert "two-releases-analysis.json" in written
    assert "two-releases-report.html" in written
    # The block switches to wet friction before its last ramp: the fits keep the dry points
    # only, and say so (issue 23, point 2); the repr stays a few lines (point 8).
    result = namespace["result"]
    assert any("changes friction (dry from 0 s, wet from" in n for n in result.notes)
    assert result.recording.time[result.fit_points].max() < 6.04
    assert "'dry' set" in result.true_parameters_source
    assert len(repr(result).splitlines()) <= 8


def test_top_level_names_resolve():
    import rollerrig

    missing = [name for name in rollerrig.__all__ if not hasattr(rollerrig, name)]
    assert not missing
