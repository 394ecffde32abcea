"""The one error type users see: a clear, one-line message (README, Errors)."""


class WheelrailError(ValueError):
    """Bad input or a reported numerical failure.

    The message is one line that says what is wrong, where, with which value, and what is allowed.
    The command line prints it as it is, without a traceback.
    """
