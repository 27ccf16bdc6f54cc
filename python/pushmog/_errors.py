"""The exceptions pushmog raises. Each is a ``PushmogError`` and also the built-in exception it was
before these classes existed (``ValueError`` for bad input, ``OSError`` for files, ``RuntimeError``
for the rest), so ``except ValueError`` still catches a bad scene and ``except pushmog.SceneError``
catches it alone. Errors from the planner carry the culprit as attributes where there is one:
``object``, ``other``, ``index``, ``field``, ``component``, ``depth``, ``line``, ``column``, ``trip``,
``feature``."""

from __future__ import annotations


class PushmogError(Exception):
    """Any error pushmog raises on purpose."""


class SceneError(PushmogError, ValueError):
    """A scene that is not valid: an object's outline, height or pose, two objects overlapping, a
    duplicate id, a scene document that does not parse, or a scene the generator cannot place."""


class SettingsError(PushmogError, ValueError):
    """A setting out of range or unknown, an unknown policy or executor name, or a setting that asks
    for a part this build left out (its ``feature`` attribute names the Cargo feature)."""


class FormatError(PushmogError, ValueError):
    """A document (plan, trip, object set, settings) that does not parse as its format."""


class FileError(PushmogError, OSError):
    """A file that cannot be read or written, or a log another process is writing."""


class PlanError(PushmogError, RuntimeError):
    """A planning or execution failure: a plan the verifier refuses, a fault of an executor, a call
    out of order."""
