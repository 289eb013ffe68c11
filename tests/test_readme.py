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
    exec(compile(_notebook_block(), str(README), "exec"), {"__name__": "readme"})
    printed = capsys.readouterr().out
    assert "ramp" in printed  # the analysis found the ramps of the simulated protocol
    assert (tmp_path / "two-releases.tdms").is_file()
    written = sorted(p.name for p in (tmp_path / "notebook-output").iterdir())
    assert "two-releases-analysis.json" in written
    assert "two-releases-report.html" in written


def test_top_level_names_resolve():
    import rollerrig

    missing = [name for name in rollerrig.__all__ if not hasattr(rollerrig, name)]
    assert not missing
