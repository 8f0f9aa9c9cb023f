"""Exceptions raised by heatdata.

Every error names the file, object or view it concerns and what is wrong with it,
so a failed batch job can be traced to its input without a debugger.
"""


def did_you_mean(word: object, choices) -> str:
    """`` (did you mean X?)`` for the choice nearest a mistyped ``word`` (difflib's ratio 0.6 or more), else ``""``:
    the tail of an error that names a library, descriptor, kind or object that does not exist."""
    import difflib

    if not isinstance(word, str):
        return ""
    near = difflib.get_close_matches(word, [str(c) for c in choices], n=1, cutoff=0.6)
    return f" (did you mean {near[0]}?)" if near else ""


class HeatdataError(Exception):
    """Base class of every error heatdata raises on purpose."""


class ModelError(HeatdataError):
    """A 3D model file is missing, unreadable, empty or has no faces."""


class RenderError(HeatdataError):
    """A partial view could not be rendered (no valid pixel, bad camera)."""


class ViewError(HeatdataError):
    """A partial view cannot be described (too small, no boundary, NaN coordinates)."""


class SpecError(HeatdataError, ValueError):
    """A descriptor spec is wrong: an unknown kind, an option out of range, a fit of other shapes, or a fitted kind
    used unfitted. The caller's mistake, never a view's: batch code does not turn it into a NaN row."""


class SpectrumError(HeatdataError):
    """The Laplace-Beltrami spectrum could not be computed to the requested accuracy."""


class StitchError(HeatdataError):
    """Two meshes cannot be stitched (no boundary, too short, not a 2-manifold)."""


class RumpError(HeatdataError):
    """Landmarks or a rump surface HBRD cannot use."""


class ConfigError(HeatdataError):
    """The workflow's config asks for something the run cannot do (the message names the key)."""


class OutputError(HeatdataError):
    """An output cannot be written: its folder is missing or read-only, it is a folder, or it is one of the inputs."""


class LibraryError(HeatdataError):
    """A library file cannot be used: not one, damaged, of another layout, or built by a heatdata that describes
    views differently."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program stands so that it unwinds as from Ctrl-C and removes its temporary files
    (:func:`heatdata.log.terminate_as_interrupt`)."""
