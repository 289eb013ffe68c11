"""The experiment figure drawn by a helper process that imports matplotlib while the caller
solves: :class:`FigureProcess` (``rollerrig simulate``).

A fresh ``rollerrig simulate`` spent about 0.4 s importing matplotlib and 0.3-0.4 s drawing and
encoding its figure, all after the solve and on one core. A helper process started before the
solve imports matplotlib on another core meanwhile, then draws while the command writes its
other files: the command waits only for what is left of the drawing.

Where matplotlib is imported already (a notebook, a test session) there is no import to hide
and the figure is drawn in the calling process, as on a machine with one core. Whatever the
helper could not do (it did not start, it died, it raised) is done again in the calling
process, so the figure and its errors are those of the in-process path; the provenance
embedded in the figure is the caller's (its command, inputs and parameters), handed over.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path

__all__ = ["FigureProcess", "draw_experiment_figure"]

HELPER_TIMEOUT = 120.0
"""Longest wait for the helper's figure [s], after which it is stopped and the figure drawn in
the calling process (the helper drew the default figure in under a second)."""


def draw_experiment_figure(results, title: str, path: str | os.PathLike, record=None) -> Path:
    """Draw the six-panel experiment figure of ``results`` into ``path`` (PNG, SVG or PDF),
    laid out already: drawn once, at :data:`~rollerrig.report.twin.EXPERIMENT_FIGURE_DPI`, with
    the provenance ``record`` (:func:`rollerrig.output.provenance`; a new one when None)."""
    from rollerrig.output import save_figure
    from rollerrig.report.twin import EXPERIMENT_FIGURE_DPI, experiment_figure

    fig = experiment_figure(results, title=title)
    return save_figure(fig, path, dpi=EXPERIMENT_FIGURE_DPI, tight=False, metadata=record)


class FigureProcess:
    """The experiment figure, drawn by a helper process started now (see the module).

    Use it as a context manager around the run: :meth:`submit` hands the results over once
    they are there, :meth:`finish` waits for the figure (or draws it here), and leaving the
    context stops a helper that is still running and removes what it was handed.

    Parameters
    ----------
    enabled : bool
        False draws in the calling process, with no helper (``--no-figure`` needs neither).
    """

    def __init__(self, enabled: bool = True) -> None:
        self._proc: subprocess.Popen | None = None
        self._job: tuple | None = None
        self._handover: Path | None = None
        from rollerrig._machine import available_cores

        if not enabled or "matplotlib" in sys.modules or available_cores() < 2:
            return
        import rollerrig

        # The helper imports this very package, wherever it was imported from here.
        root = str(Path(rollerrig.__file__).parents[1])  # as spelled on its sys.path
        try:
            self._proc = subprocess.Popen(
                [sys.executable, "-c", _BOOTSTRAP, root],
                stdin=subprocess.PIPE,
                stdout=subprocess.DEVNULL,  # what goes wrong there is done again here
                stderr=subprocess.DEVNULL,
                env={**os.environ, "MPLBACKEND": "Agg"},
            )
        except OSError:
            self._proc = None

    @property
    def helped(self) -> bool:
        """True while a helper process was started and has not failed."""
        return self._proc is not None

    def __enter__(self) -> FigureProcess:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def submit(self, results, title: str, path: str | os.PathLike, record) -> None:
        """Hand the figure's results, title, target path and provenance record over: to the
        helper, which starts drawing now, or kept for :meth:`finish`."""
        self._job = (results, title, Path(path), record)
        if self._proc is None:
            return
        try:
            fd, name = tempfile.mkstemp(prefix="rollerrig-figure-", suffix=".pickle")
            self._handover = Path(name)
            with os.fdopen(fd, "wb") as f:
                pickle.dump(self._job, f, protocol=pickle.HIGHEST_PROTOCOL)
            self._proc.stdin.write(name.encode() + b"\n")
            self._proc.stdin.close()
        except (OSError, pickle.PicklingError, ValueError):
            self._stop()

    def finish(self) -> Path:
        """The figure's path once it is written: the helper's, else drawn here."""
        if self._job is None:
            raise RuntimeError("FigureProcess.finish: nothing was submitted")
        results, title, path, record = self._job
        if self._proc is not None:
            try:
                self._proc.wait(timeout=HELPER_TIMEOUT)
            except subprocess.TimeoutExpired:
                self._stop()
            else:
                done = self._proc.returncode == 0 and path.is_file()
                self._proc = None
                if done:
                    self._drop_handover()
                    return path
        self._drop_handover()
        return draw_experiment_figure(results, title, path, record)

    def close(self) -> None:
        """Stop a helper still running and remove the handed-over file."""
        self._stop()
        self._drop_handover()

    def _stop(self) -> None:
        proc, self._proc = self._proc, None
        if proc is None:
            return
        try:
            proc.stdin.close()  # a helper still importing then finds no job and ends
        except OSError:
            pass
        if proc.poll() is None:
            proc.kill()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass

    def _drop_handover(self) -> None:
        if self._handover is not None:
            self._handover.unlink(missing_ok=True)
            self._handover = None


def _warm_up() -> None:
    """Draw a small figure with text once, while the caller solves: the font's loading and
    the first text layout are then paid before the job arrives, not after."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2.0, 1.5))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.plot([0.0, 1.0], [0.0, 1.0], label="0.5 s")
    ax.set_title("(a) torque")
    ax.set_ylabel("T [N.m]")
    ax.legend()
    fig.canvas.draw()


def _helper() -> int:
    """The helper process: import what drawing needs, then draw the job named on stdin."""
    import matplotlib

    matplotlib.use("Agg")
    import rollerrig.output  # save_figure and its imports, before the job arrives
    import rollerrig.report.twin  # noqa: F401

    _warm_up()
    line = sys.stdin.buffer.readline().strip()
    if not line:  # the caller stopped before it had results
        return 0
    with open(os.fsdecode(line), "rb") as f:
        results, title, path, record = pickle.load(f)  # the caller's own file (mkstemp, 0600)
    draw_experiment_figure(results, title, path, record)
    return 0


def _main() -> None:
    """The helper process's entry (:data:`_BOOTSTRAP`)."""
    try:
        status = _helper()
    except KeyboardInterrupt:  # Ctrl-C reaches the helper too: the caller reports it
        status = 130
    # The figure is written and closed (atomically): end without the interpreter's teardown
    # of matplotlib's modules, which the caller would wait for (0.2-0.3 s).
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


_BOOTSTRAP = (
    "import sys; root = sys.argv.pop(); "
    "root in sys.path or sys.path.insert(0, root); "
    "from rollerrig.report.figure_process import _main; _main()"
)
"""The helper's command: the folder the caller imported rollerrig from goes first on its path
where the helper would not find it there anyway (nothing is put before the standard library
of an installed package's interpreter)."""
