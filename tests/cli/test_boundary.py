"""The error boundary: one ``error:`` line (exit 2) or one ``internal error`` line (exit 3),
never a traceback, never a partial output; missing extras named; signals end a command
cleanly; each DomainWarning printed once.

The subprocess tests run ``rollerrig`` in a fresh interpreter (``-c`` with a prelude that hides
an optional package or makes a write slow), as a user's shell would.
"""

import os
import signal
import subprocess
import sys
import textwrap
import warnings

import pytest

from rollerrig.cli import app
from rollerrig.cli._outputs import LOCK_NAME, STAGE_PREFIX


def _no_traceback(result):
    assert "Traceback" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


def _files(folder):
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def test_missing_file_is_one_error_line(tmp_path, runner):
    missing = tmp_path / "nope.tdms"
    for args in (["analyze", str(missing)], ["filters", str(missing)]):
        result = runner.invoke(app, [*args, "--out", str(tmp_path / "out")])
        assert result.exit_code == 2, result.output
        assert result.output.startswith("error:") and "nope.tdms" in result.output
        assert len(result.output.strip().splitlines()) == 1
        _no_traceback(result)
    assert not (tmp_path / "out").exists()


def test_internal_error_is_one_line_exit_3_and_debug_shows_the_traceback(
    tmp_path, monkeypatch, runner
):
    import rollerrig.report.contact as figures

    def broken(*args, **kwargs):
        raise ZeroDivisionError("something inside broke")

    monkeypatch.setattr(figures, "creep_curve_figure", broken)
    args = ["contact", "--out", str(tmp_path)]
    result = runner.invoke(app, args)
    assert result.exit_code == 3, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith("internal error: ZeroDivisionError: something inside broke")
    assert "please report" in line
    _no_traceback(result)
    assert _files(tmp_path) == []  # no staging folder, no lock file
    # --debug (or ROLLERRIG_DEBUG=1) shows the traceback as well, same exit code.
    result = runner.invoke(app, ["--debug", *args])
    assert result.exit_code == 3
    assert "Traceback" in result.output and "ZeroDivisionError" in result.output
    monkeypatch.setenv("ROLLERRIG_DEBUG", "1")
    result = runner.invoke(app, args)
    assert result.exit_code == 3 and "Traceback" in result.output


def test_a_signal_swallowed_by_compiled_code_is_still_an_interruption(
    tmp_path, monkeypatch, runner
):
    # SIGTERM while numba compiles: the handler's exception is raised inside an LLVM callback,
    # swallowed there ("Exception ignored ... ctypes callback"), and numba then fails with
    # RuntimeError("no compiled object yet ..."). The boundary must report the signal, not an
    # internal error, and print no traceback of the swallowed exception.
    import rollerrig.report.contact as figures
    from rollerrig.cli import _boundary

    def compile_interrupted(*args, **kwargs):
        try:
            _boundary._on_signal(signal.SIGTERM, None)
        except BaseException:  # what the ctypes callback does with it
            pass
        raise RuntimeError("no compiled object yet for <Library 'integrate'>")

    monkeypatch.setattr(figures, "creep_curve_figure", compile_interrupted)
    result = runner.invoke(app, ["contact", "--out", str(tmp_path)])
    assert result.exit_code == 128 + signal.SIGTERM, result.output
    (line,) = result.output.strip().splitlines()
    assert line == "error: interrupted by SIGTERM; --out holds no partial output of this run"
    assert _files(tmp_path) == []
    for s in (signal.SIGTERM, signal.SIGINT):  # handlers restored after the command
        assert signal.getsignal(s) is not _boundary._on_signal


def test_a_broken_import_inside_rollerrig_is_an_internal_error(tmp_path, monkeypatch, runner):
    import rollerrig.report.contact as figures

    def broken(*args, **kwargs):
        raise ImportError("cannot import name 'x' from 'rollerrig.foo'", name="rollerrig.foo")

    monkeypatch.setattr(figures, "creep_curve_figure", broken)
    result = runner.invoke(app, ["contact", "--out", str(tmp_path)])
    assert result.exit_code == 3, result.output
    assert result.output.startswith("internal error: ImportError")


def test_a_reader_that_names_the_extra_keeps_its_sentence(tmp_path, monkeypatch, runner):
    import rollerrig.recordings.readers as readers

    def no_nptdms(*args, **kwargs):
        raise ImportError("reading TDMS files needs nptdms: pip install 'rollerrig[io]'")

    monkeypatch.setattr(readers, "read_recording", no_nptdms)
    path = tmp_path / "x.tdms"
    path.write_bytes(b"TDSm")
    result = runner.invoke(app, ["filters", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "reading TDMS files needs nptdms: pip install 'rollerrig[io]'" in result.output
    _no_traceback(result)


def test_a_missing_reader_package_names_the_extra_of_the_job(tmp_path, monkeypatch, runner):
    import rollerrig.recordings.readers as readers

    def no_nptdms(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'nptdms'", name="nptdms")

    monkeypatch.setattr(readers, "read_recording", no_nptdms)
    path = tmp_path / "x.tdms"
    path.write_bytes(b"TDSm")
    result = runner.invoke(app, ["filters", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert result.output == "error: rollerrig filters needs nptdms: pip install 'rollerrig[io]'\n"


def test_error_messages_keep_brackets(tmp_path, runner, adhesion_csv):
    # A channel map entry and the extra to install are named with brackets: both survive.
    rec = adhesion_csv(tmp_path / "test.csv")
    cmap = tmp_path / "map.toml"
    cmap.write_text('[time]\ncolumn = "time [s]"\nunit = "s"\n[channels.torque]\ncolumn = "Tq"\n')
    args = ["filters", str(rec), "--channels", str(cmap), "--out", str(tmp_path / "out")]
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert "[channels.torque]" in result.output
    _no_traceback(result)


# --- DomainWarning -------------------------------------------------------------------------


def test_each_domain_warning_is_printed_once_and_listed_in_the_manifest(tmp_path, runner):
    # 200 kN on 5 mm radii: the Hertz semi-axis is a fifth of the relative radius (issue 8):
    # Hertz is extrapolated (a load beyond 200 kN is refused as typed in N).
    result = runner.invoke(
        app,
        ["contact", "--load-kn", "200", "--roller-radius-mm", "5", "--wheel-radius-mm", "5",
         "--out", str(tmp_path)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    lines = [ln for ln in result.output.splitlines() if ln.startswith("warning:")]
    assert lines and all("Hertz contact outside its domain" in ln for ln in lines)
    assert len(lines) == len(set(lines))  # each once, though computed for 3000 creep values
    import json

    manifest = json.loads((tmp_path / "contact-run.json").read_text())
    assert [f"warning: {w}" for w in manifest["warnings"]] == lines


def test_a_domain_warning_is_one_line_and_other_warnings_are_left_alone(
    tmp_path, monkeypatch, runner
):
    from rollerrig._warnings import DomainWarning
    from rollerrig.cli import _options

    def load_rig(rig_file):
        for _ in range(3):
            warnings.warn("torque request 1e5 N.m beyond 852 N.m", DomainWarning, stacklevel=1)
        warnings.warn("something else", UserWarning, stacklevel=1)
        raise SystemExit(0)  # enough: no need to compute the contact

    monkeypatch.setattr(_options, "load_rig", load_rig)
    monkeypatch.setattr("rollerrig.cli.contact.load_rig", load_rig)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = runner.invoke(app, ["contact", "--out", str(tmp_path)])
    assert result.output.splitlines() == ["warning: torque request 1e5 N.m beyond 852 N.m"]
    assert [str(w.message) for w in caught] == ["something else"]


# --- Missing optional packages (a core install) --------------------------------------------

_WITHOUT = textwrap.dedent(
    """
    import sys
    for name in sys.argv[1].split(","):
        sys.modules[name] = None  # import of it fails as if it were not installed
    from rollerrig.cli import app
    app(sys.argv[2:], prog_name="rollerrig")
    """
)
_OPTIONAL = "numba,xarray,h5netcdf,pandas,pyarrow,nptdms,asammdf,h5py"


def _without(modules: str, *args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", _WITHOUT, modules, *args],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=cwd,
        env={**os.environ, "MPLBACKEND": "Agg", "COLUMNS": "100"},
    )


def test_help_works_without_any_optional_package():
    for args in (["--help"], ["simulate", "--help"], ["analyze", "--help"]):
        done = _without(_OPTIONAL, *args)
        assert done.returncode == 0, done.stderr
        assert "Usage:" in done.stdout


@pytest.mark.parametrize(
    ("missing", "args", "expected"),
    [
        ("numba", ["simulate"], "rollerrig simulate needs numba: pip install 'rollerrig[twin]'"),
        (
            "h5py",
            ["simulate"],
            "rollerrig simulate --format nc needs h5py: pip install 'rollerrig[twin]'",
        ),
        ("pandas", ["filters"], "pip install 'rollerrig[io]'"),
    ],
)
def test_a_missing_optional_package_names_the_extra(
    tmp_path, adhesion_csv, missing, args, expected
):
    # On a core install simulate died with "ModuleNotFoundError: xarray" and filters with
    # "No module named 'pandas'" (issue 8); now one sentence names the extra of the job, and
    # simulate says so before it simulates. (simulate no longer needs xarray: it writes its
    # results without it, tests/cli/test_lazy.py.)
    if args == ["filters"]:
        args = [*args, str(adhesion_csv(tmp_path / "test.csv"))]
    done = _without(missing, *args, "--out", str(tmp_path / "out"))
    assert done.returncode == 2, done.stdout + done.stderr
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith("error:") and missing in line and expected in line, line
    assert "simulating" not in done.stdout
    assert not (tmp_path / "out").exists()


# --- Signals -------------------------------------------------------------------------------

_SLOW_FIGURE = textwrap.dedent(
    """
    import sys, time
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    def slow_savefig(self, fname, *args, **kwargs):  # half a figure, then a stall
        with open(fname, "wb") as fh:
            fh.write(b"\\x89PNG half a figure")
        print("writing a figure", flush=True)
        time.sleep(60)

    Figure.savefig = slow_savefig
    from rollerrig.cli import app
    app(sys.argv[1:], prog_name="rollerrig")
    """
)

_SLOW_MOVE = textwrap.dedent(
    """
    import os, sys, time
    from pathlib import Path
    out = Path(sys.argv[-1]).resolve()
    real_replace = os.replace

    def slow_replace(src, dst, *args, **kwargs):  # moving into --out takes a while
        if Path(dst).resolve().parent == out:
            print("moving", flush=True)
            time.sleep(0.3)
        return real_replace(src, dst, *args, **kwargs)

    os.replace = slow_replace
    from rollerrig.cli import app
    app(sys.argv[1:], prog_name="rollerrig")
    """
)


def _run_until(script: str, marker: str, args: list[str], signum: int):
    proc = subprocess.Popen(
        [sys.executable, "-c", script, *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    try:
        for line in proc.stdout:
            if line.strip() == marker:
                proc.send_signal(signum)
                break
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, err


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_while_a_figure_is_written_leaves_nothing(tmp_path, signum):
    out = tmp_path / "out"
    out.mkdir()
    (out / "earlier.txt").write_text("an earlier run's file")
    code, err = _run_until(_SLOW_FIGURE, "writing a figure", ["contact", "--out", str(out)], signum)
    assert code == 128 + signum, err
    name = signal.Signals(signum).name
    assert err.strip() == f"error: interrupted by {name}; --out holds no partial output of this run"
    # No temporary file, no staging folder, no lock: only what was there before.
    assert _files(tmp_path) == ["earlier.txt", "out"]


def test_sigterm_while_the_outputs_move_in_waits_for_the_complete_set(tmp_path):
    out = tmp_path / "out"
    code, err = _run_until(_SLOW_MOVE, "moving", ["contact", "--out", str(out)], signal.SIGTERM)
    assert code == 128 + signal.SIGTERM, err
    assert "interrupted by SIGTERM" in err
    names = _files(out)
    assert names == [
        "contact-creep-curves.png",
        "contact-report.json",
        "contact-run.json",
        "contact-vs-roller-radius.png",
    ]
    assert not any(n.startswith((STAGE_PREFIX, ".")) or n == LOCK_NAME for n in names)
