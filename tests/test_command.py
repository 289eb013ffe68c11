"""The console script's entry (:mod:`rollerrig._command`)."""

import signal
import subprocess
import sys

import pytest

from rollerrig import _command


def test_sigint_before_the_command_takes_over_exits_130_without_a_traceback(capsys):
    with pytest.raises(SystemExit) as ended:
        _command._interrupted(signal.SIGINT, None)
    assert ended.value.code == 130
    assert capsys.readouterr().err == "interrupted\n"


def test_the_entry_runs_the_command_and_restores_the_handler():
    # The handler it restores is the one the process had: Python's default_int_handler, or
    # SIG_IGN where the parent ignores SIGINT (a shell's background job: a CI run started with
    # `&` had failed here on the test, not on the command).
    code = (
        "import signal, sys; sys.argv = ['rollerrig', '--version']\n"
        "before = signal.getsignal(signal.SIGINT)\n"
        "from rollerrig._command import main\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert e.code in (0, None), e.code\n"
        "assert signal.getsignal(signal.SIGINT) is before, signal.getsignal(signal.SIGINT)\n"
        "print('ok')"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "rollerrig" in done.stdout and done.stdout.strip().endswith("ok")
