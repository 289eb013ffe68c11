"""``python -m rollerrig``: the ``rollerrig`` command (as ``python -m rollerrig.cli``)."""

from rollerrig._command import main

main()
