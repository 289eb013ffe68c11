"""The error of a frame file that is malformed, non-physical or cannot carry load."""

from __future__ import annotations

from rollerrig._validation import ParameterError, Problem

__all__ = ["MAX_PROBLEMS_SHOWN", "FrameFileError"]

MAX_PROBLEMS_SHOWN = 100
"""Problems listed in one :class:`FrameFileError`; the rest are counted in a last line."""


class FrameFileError(ParameterError):
    """A frame file is malformed, non-physical, or describes a frame that cannot carry load.

    One line per problem, each naming the file and the key (``members.column.nodes``) and what
    to change.

    Attributes
    ----------
    origin : str
        The file (or ``"<dict>"``) the problems were found in.
    problems : list of str
        One line per problem (at most :data:`MAX_PROBLEMS_SHOWN`, then one line counting the
        rest).
    """

    def __init__(self, origin: str, problems: list[Problem | str]):
        self.origin = origin
        self.problems = [
            p.format(origin) if isinstance(p, Problem) else f"{origin}: {p}"
            for p in problems[:MAX_PROBLEMS_SHOWN]
        ]
        if len(problems) > MAX_PROBLEMS_SHOWN:
            self.problems.append(
                f"{origin}: ... and {len(problems) - MAX_PROBLEMS_SHOWN} more problems "
                "(fix these first)"
            )
        super().__init__("\n".join(self.problems))
