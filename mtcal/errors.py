"""Exceptions with messages meant for people: name the file, row and problem."""


class InputError(ValueError):
    """Bad input (file, row, value); the CLI prints it without a traceback and exits 2."""
