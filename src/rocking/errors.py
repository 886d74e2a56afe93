"""Exceptions raised by the package.

Every error caused by what a user passed in (a parameter, a file, a row of a table) is an
:class:`InputError`; it is also a :class:`ValueError`, so ``except ValueError`` keeps working.
The command-line interface prints these in one line and exits with status 1.
"""


class RockingError(Exception):
    """Base class of the package's own errors."""


class InputError(RockingError, ValueError):
    """Bad input: the message names the parameter, file or row and what was wrong."""


class BackendError(RockingError):
    """The computing backend failed (e.g. a Dask cluster lost its workers): not the input's
    fault, nor a bug; finished chunks are kept, so the same call resumes once it works again."""
