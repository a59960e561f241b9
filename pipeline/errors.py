"""Exceptions shared by the whole package."""


class InputError(ValueError):
    """Bad input (a file, a field, a value) that the user can fix.

    The message names what is wrong (file, field or value) and how to fix it.
    The command line prints it without a traceback and exits with status 2.
    """


class OutputError(InputError):
    """A result could not be written (read-only folder, full disk, a folder in the way).

    The message names the file and the cause, says what was kept (e.g. the
    checkpoint of the finished tasks) and how to go on. Handled like
    :class:`InputError`: one line, no traceback, exit status 2.
    """


class RecordWarning(UserWarning):
    """A record that loads but looks unfit as it is (an offset, a drifting velocity).

    The message names the record, what is wrong and the processing step that
    fixes it. The command line prints it as one line.
    """


class HazardWarning(UserWarning):
    """A site-risk result that rests on extrapolation (a hazard curve that ends before a fragility's median).

    The message names the hazard file, the site, the cells affected and where the bounds are.
    The command line prints it as one line, like :class:`RecordWarning`.
    """
