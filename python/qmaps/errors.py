"""The exceptions of qmaps, raised by the engine and the loader alike (the same messages as the
qmaps program's `qmaps: error:` lines)."""


class Error(Exception):
    """Any error qmaps reports."""


class ConfigError(Error, ValueError):
    """A bad configuration, parameter or argument: the message names the key and its line."""


class FileError(Error, OSError):
    """A file that cannot be read or written, or is not a qmaps run: the message names it."""


class UnsupportedError(Error):
    """An instruction set this CPU or this build lacks."""
