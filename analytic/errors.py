"""The errors every part of the toolkit raises on bad input (one-line messages naming the parameter and the
fix). Light (no numpy): a front end catches them before it has loaded anything heavy."""


class ParameterError(ValueError):
    """An invalid mechanism parameter; the message is one line that names it and the fix."""


class FileError(ParameterError):
    """A mechanism file that cannot be used; the message is one line naming the file and the fix."""


class AssemblyError(ParameterError):
    """A mechanism that cannot be assembled (or locks) at a requested input position."""
