"""``python -m rollerrig.cli``: the ``rollerrig`` command."""

from rollerrig.cli import main

main()
