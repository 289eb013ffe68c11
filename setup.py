"""Build hook: record the git commit of the source in the built package.

Everything else about the package is in ``pyproject.toml``. A wheel built from a git checkout
(``pip install .`` from a clone, as the README says) carries ``rollerrig/_build_commit.txt``, so
that the provenance of every output names the commit even when the installed package no longer
sits in a work tree (:func:`rollerrig.output.provenance.package_commit`). Without git, or from an
sdist, nothing is written and the provenance says why the commit is unknown.
"""

import subprocess
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py


def _git(*args: str) -> str | None:
    try:
        done = subprocess.run(
            ["git", *args], capture_output=True, text=True, timeout=10, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


class BuildPyWithCommit(build_py):
    def run(self):
        super().run()
        head = _git("rev-parse", "HEAD")
        if not head or self.editable_mode:  # an editable install finds the work tree itself
            return
        dirty = _git("status", "--porcelain", "--", "src")
        target = Path(self.build_lib) / "rollerrig" / "_build_commit.txt"
        target.write_text(head + ("-dirty" if dirty else "") + "\n", encoding="ascii")


setup(cmdclass={"build_py": BuildPyWithCommit})
