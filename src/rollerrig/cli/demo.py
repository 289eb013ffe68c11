"""``rollerrig demo``: the end-to-end job on the bundled rig (see :mod:`rollerrig.demo`)."""

from __future__ import annotations

from rollerrig.cli._console import QuietOption, console, print_written
from rollerrig.cli._options import DEFAULT_OUT, FigureFormat, FigureFormatOption, OutOption
from rollerrig.cli._outputs import command_outputs
from rollerrig.cli.recordings import print_analysis

__all__ = ["demo"]


def demo(
    out: OutOption = DEFAULT_OUT,
    quiet: QuietOption = False,
    figure_format: FigureFormatOption = FigureFormat.png,
) -> None:
    """End to end on the bundled rig: simulate, record, analyse, report.

    \b
    1. simulates the 30 km/h dry adhesion test on the digital twin (1 kHz);
    2. writes what the rig's DAQ would record (250 Hz, motor lines, ripple, noise, encoders) as
       an NI TDMS file, with the truth beside it (NetCDF);
    3. records free rolling at 5, 10, 20 and 30 km/h as ASAM MDF4 files;
    4. analyses the test and writes the HTML report; explains the free-rolling spectra.
    """
    from rollerrig._optional import EXTRAS, require
    from rollerrig.demo import run_demo
    from rollerrig.rig.parameters import default_rig

    # Every optional package the demo will need, checked before it simulates (the error names
    # the extra: `all`), not after 15 s when it first writes a TDMS file.
    for module in sorted(set().union(*EXTRAS.values())):
        require(module, "all", "rollerrig demo")

    with command_outputs(out, run="demo", rig=default_rig()) as stage:
        paths = run_demo(
            out, console, workdir=stage.dir, figure_format=FigureFormat(figure_format).value
        )
    json_names = [n for n in paths if str(n).endswith("-analysis.json")]
    print_analysis(paths["result"], f"{out / json_names[0]}, 'notes'" if json_names else None)
    lines = ", ".join(f"{f:.3f} Hz" for f in paths["speed_independent"]) or "none"
    console.print(
        f"speed-independent lines in the free-rolling spectra: {lines} (no line is injected "
        "into the demo's recordings: what is listed was found, not put there)"
    )
    print_written(stage.written)
