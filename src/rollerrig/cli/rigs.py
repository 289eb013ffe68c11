"""``rollerrig rig list``: the rig parameter sets that ``--rig NAME`` loads.

The bundled sets and those of installed packages (entry-point group ``rollerrig.rigs``), each
with its origin and file; see :mod:`rollerrig.rig.library`.
"""

from __future__ import annotations

import typer

from rollerrig.cli._console import console

rig_app = typer.Typer(
    help="Rig parameter sets by name (for --rig NAME on every command that takes --rig).",
    no_args_is_help=True,
    rich_markup_mode=None,
)


@rig_app.command("list")
def list_sets() -> None:
    """List the rig sets: name, origin (bundled or the package that ships it), title and file.

    A lab ships its own set in a package with an entry point in the group rollerrig.rigs (see
    rollerrig.rig.library); it then appears here and loads with --rig NAME.
    """
    from rollerrig.rig.library import rig_sets

    sets = rig_sets()
    width = max(len(name) for name in sets)
    for name, entry in sets.items():
        console.print(f"{name:<{width}}  {entry.origin}  {entry.title}")
        if entry.problem:
            console.print(f"{'':<{width}}  cannot be loaded: {entry.problem}")
        else:
            console.print(f"{'':<{width}}  {entry.description}")
            console.print(f"{'':<{width}}  file: {entry.path}")
