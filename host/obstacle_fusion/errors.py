"""Errors that name a user's mistake and what to do about it."""

from __future__ import annotations


class UserError(Exception):
    """A problem with the user's input or setup; the CLI prints it without a traceback."""

    def __init__(self, message: str, exit_code: int = 2) -> None:
        super().__init__(message)
        self.exit_code = exit_code
