"""``rollerrig rig list`` and ``rig show``: the rig parameter sets that ``--rig NAME`` loads.

The bundled sets and those of installed packages (entry-point group ``rollerrig.rigs``), each
with its origin and file; see :mod:`rollerrig.rig.library`.
"""

from __future__ import annotations

from typing import Annotated

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


@rig_app.command("show")
def show_set(
    rig: Annotated[
        str, typer.Argument(help="A set's name (rollerrig rig list) or a rig TOML file.")
    ],
    section: Annotated[
        str | None,
        typer.Option(help="Only this section (e.g. stiffness, sensors, arm)."),
    ] = None,
) -> None:
    """Show a rig set's values: each key with its value and unit as the file states them, and
    its basis (the source it is taken from, or the assumption it rests on)."""
    import shutil

    from rich.table import Table

    from rollerrig._validation import did_you_mean
    from rollerrig.cli._boundary import UserError
    from rollerrig.rig.library import resolve_rig
    from rollerrig.rig.parameters import load_rig

    path = resolve_rig(rig)
    params = load_rig(path)
    entries = params.provenance
    if section is not None:
        sections = sorted({key.split(".")[0] for key in entries})
        if section not in sections:
            raise UserError(
                f"--section {section!r}: no such section{did_you_mean(section, sections)}; the "
                f"set has {sections}"
            )
        entries = {k: v for k, v in entries.items() if k.split(".")[0] == section}
    width = max(60, min(160, shutil.get_terminal_size((120, 24)).columns))
    table = Table(title=f"{params.meta.name} ({path})", width=width)
    for col, justify in (("key", "left"), ("value", "right"), ("unit", "left"),
                         ("basis", "left")):  # fmt: skip
        table.add_column(col, justify=justify, overflow="fold")
    for key, entry in entries.items():
        if "source" in entry:
            basis = f"source: {entry['source']}"
        elif "assumption" in entry:
            basis = f"assumption: {entry['assumption']}"
        else:
            basis = "–"
        table.add_row(key, f"{entry.get('value')!s}", str(entry.get("unit", "")), basis)
    console.print(table)
