"""Exceptions shared by the whole package."""


class InputError(ValueError):
    """Bad input (a file, a field, a value) that the user can fix.

    The message names what is wrong (file, field or value) and how to fix it.
    The command line prints it without a traceback and exits with status 2.
    """
