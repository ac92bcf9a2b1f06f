"""The exceptions of qmaps, raised by the engine and the loader alike (the same messages as the
qmaps program's `qmaps: error:` lines)."""


class Error(Exception):
    """Any error qmaps reports: the base class of ConfigError, FileError and UnsupportedError.

    Example::

        try:
            run = qmaps.run("my-run.toml")
        except qmaps.Error as e:
            print(f"qmaps: error: {e}")
    """


class ConfigError(Error, ValueError):
    """A bad configuration, parameter or argument: the message names the key and its line
    (``qmaps run`` exits 2 for it). It is also a ValueError.

    Example::

        try:
            qmaps.run("ensembles/presets/suris.toml", map={"h": -1.0})
        except qmaps.ConfigError as e:
            print(e)      # names [map] and h
    """


class FileError(Error, OSError):
    """A file that cannot be read or written, or is not a qmaps run: the message names it
    (``qmaps run`` exits 3 for it). It is also an OSError.

    Example::

        try:
            run = qmaps.load("missing.h5")
        except qmaps.FileError as e:
            print(e)      # missing.h5: no such file
    """


class UnsupportedError(Error):
    """An instruction set this CPU or this build lacks, named by ``simd=`` (``qmaps run`` exits
    4 for it).

    Example::

        try:
            run = qmaps.run("ensembles/presets/suris.toml", simd="avx512")
        except qmaps.UnsupportedError:
            run = qmaps.run("ensembles/presets/suris.toml")     # the best this CPU has
    """
