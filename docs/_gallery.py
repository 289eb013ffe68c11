"""Helpers of the executed gallery (sphinx-gallery), named by ``conf.py`` as strings."""

from __future__ import annotations

import warnings


def _category_and_message(message, category, filename, lineno, line=None):
    return f"{category.__name__}: {message}\n"


def plain_warnings(gallery_conf, fname):
    """Show a warning an example raises as ``Category: message`` in its printed output.

    Python's default format starts with the path of the script on the machine that built the
    site and repeats the source line; a reader sees the warning's class and its text. Run before
    each example (``reset_modules``); the downloaded script warns as any script does.
    """
    warnings.formatwarning = _category_and_message
