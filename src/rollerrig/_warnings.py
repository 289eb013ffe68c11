"""Warnings of the package: a model used outside its domain of validity.

A :class:`DomainWarning` says that a result was computed, but by a model whose assumptions the
inputs violate (a Hertz contact ellipse as large as the radii of the bodies, a torque request
beyond what the drive can deliver, ...). The message names the quantity, its value with its
unit and the limit. The CLI prints each one as a ``warning:`` line; in Python they are ordinary
:mod:`warnings` (issued with ``warnings.warn(message, DomainWarning, stacklevel=2)``) and can be
filtered or turned into errors.

Examples
--------
>>> import warnings
>>> from rollerrig.contact.hertz import hertz_contact
>>> with warnings.catch_warnings():
...     warnings.simplefilter("error", DomainWarning)
...     hertz_contact(1e9, 0.348, 0.291, 0.452, 1.89)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
rollerrig._warnings.DomainWarning: Hertz contact outside its domain: ...
"""

from __future__ import annotations

__all__ = ["DomainWarning"]


class DomainWarning(UserWarning):
    """A model was used outside its domain of validity; the result is an extrapolation."""
