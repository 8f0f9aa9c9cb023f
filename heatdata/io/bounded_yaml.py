"""YAML from files heatdata did not write: bounded in size, without aliases, and never echoed whole.

PyYAML's ``safe_load`` builds no objects but keeps YAML's aliases: ``*name`` repeats an anchored value by reference,
so 400 bytes of nested aliases ("billion laughs") stand for 10^9 values. The loading itself is fast; whatever walks
the value afterwards (a schema, a type conversion, a message that quotes it) is not. A camera file or a workflow
config has no use for aliases, so they are refused, with a size cap on the text.
"""

from __future__ import annotations

import reprlib

import yaml

from heatdata.errors import HeatdataError

#: the largest YAML text read (an intrinsics file holds six numbers; the workflow's whole config is 30 kB)
MAX_YAML_BYTES = 1 << 20
_BRIEF = reprlib.Repr()
_BRIEF.maxlevel, _BRIEF.maxdict, _BRIEF.maxlist, _BRIEF.maxtuple, _BRIEF.maxset = 2, 4, 4, 4, 4
_BRIEF.maxstring, _BRIEF.maxlong, _BRIEF.maxother = 40, 40, 40


def brief(value: object) -> str:
    """A value's repr cut short, whatever its size or depth: at most a few dozen characters, in bounded time.

    Parameters
    ----------
    value : object

    Returns
    -------
    str
    """
    return _BRIEF.repr(value)


class _WithoutAliases(yaml.SafeLoader):
    """``SafeLoader`` that refuses an alias (``*name``) where it meets one, before anything walks the value."""

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            raise yaml.composer.ComposerError(
                None, None, "an alias (*name) repeats another value: write the value out instead", mark
            )
        return super().compose_node(parent, index)


def load_yaml(text: str, name: str, error: type[HeatdataError] = HeatdataError):
    """The value of a YAML text, read safely: at most :data:`MAX_YAML_BYTES`, and no alias.

    Parameters
    ----------
    text : str
        The YAML.
    name : str
        Where it came from, for the message.
    error : type
        The :class:`HeatdataError` to raise.

    Returns
    -------
    object
        What ``yaml.safe_load`` returns for a text without aliases.

    Raises
    ------
    HeatdataError
        Of type ``error``: too long, an alias, or not YAML (the parser's reason, with its line and column).
    """
    if len(text) > MAX_YAML_BYTES:
        raise error(f"{name}: {len(text):,} characters of YAML, more than the {MAX_YAML_BYTES:,} read")
    try:
        return yaml.load(text, Loader=_WithoutAliases)
    except (yaml.YAMLError, RecursionError) as exc:
        reason = " ".join(str(exc).split()).replace(' in "<unicode string>",', ",")[:300]
        reason = reason if isinstance(exc, yaml.YAMLError) else "nested too deep"
        raise error(f"{name}: not read as YAML ({reason})") from None
