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
    import shutil
    import textwrap

    from rollerrig.rig.library import rig_sets

    # One block per set: the names that load the same file (the default rig has two) together.
    names: dict[object, list[str]] = {}
    entries = {}
    for name, entry in rig_sets().items():
        key = entry.path if entry.path is not None else name
        names.setdefault(key, []).append(name)
        entries.setdefault(key, entry)
    indent = "    "
    width = max(40, min(100, shutil.get_terminal_size((100, 24)).columns) - len(indent))
    for key, entry in entries.items():
        aliases = names[key]
        label = (
            aliases[0] if len(aliases) == 1 else f"{aliases[-1]} (also: {', '.join(aliases[:-1])})"
        )
        console.print(f"{label}  [{entry.origin}]  {entry.title}", soft_wrap=True)
        text = f"cannot be loaded: {entry.problem}" if entry.problem else entry.description
        for line in textwrap.wrap(text, width, break_on_hyphens=False, break_long_words=False):
            console.print(indent + line, soft_wrap=True)
        if not entry.problem:
            console.print(f"{indent}file: {entry.path}", soft_wrap=True)
        console.print()
