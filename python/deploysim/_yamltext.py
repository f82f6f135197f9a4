"""Python values -> YAML text for deploysim's strict readers.

A profile, model or sweep built from Python dicts is written as one YAML document in
flow style and read by the same C++ reader as a file, so that the schema, the rules and
the one-line error messages are those of files (docs/file_formats.md). Keys are written
as plain scalars; strings plain where YAML reads them back as the same string (names,
paths, ``rkmk-rkf78``: messages then show them as a file's do), else double-quoted (a
number given as a string stays a string, as ``"12"`` does in a file and is refused the
same way); numbers in the shortest form that reads back exactly, non-finite
numbers as ``.nan`` / ``.inf`` (refused by the reader with its message), booleans as
``true`` / ``false``, None as ``null``; numpy scalars and arrays as numbers and lists.
"""

import json
import math
import numbers
import re

_PLAIN_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")
# Strings YAML reads back unchanged as plain scalars in flow context: a letter or '_'
# first (so no number, .inf, .nan), optionally after ./ ../ or /; no ':', '#', ',', '[',
# ']', '{', '}', quotes or control characters; no trailing space.
_PLAIN_TEXT = re.compile(r"^(?:\.{1,2}/|/)?[A-Za-z_][A-Za-z0-9_ ./+\-()]*(?<! )$")
_YAML_WORDS = {"y", "n", "yes", "no", "true", "false", "on", "off", "null"}


def _key(k):
    if isinstance(k, str) and _PLAIN_KEY.match(k) and k not in ("null", "true", "false", "yes",
                                                                 "no", "on", "off", "y", "n"):
        return k
    if isinstance(k, numbers.Number) and not isinstance(k, bool):
        return _scalar(k)
    # Anything else is quoted: the reader refuses keys that are not plain scalars,
    # naming them.
    return json.dumps(str(k))


def _key_entry(k):
    # YAML limits implicit keys to 1024 characters: longer ones as explicit keys (`? k`),
    # still plain scalars.
    text = _key(k)
    return "? " + text if len(text) > 1000 else text


def _scalar(v):
    if v is None:
        return "null"
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return "true" if bool(v) else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        if math.isnan(f):
            return ".nan"
        if math.isinf(f):
            return ".inf" if f > 0 else "-.inf"
        return repr(f)
    if isinstance(v, str):
        if _PLAIN_TEXT.match(v) and v.lower() not in _YAML_WORDS:
            return v
        return json.dumps(v, ensure_ascii=False)
    raise TypeError(f"cannot write a {type(v).__name__} into a deploysim document: {v!r}")


def to_yaml(value):
    """The YAML (flow style, one line) of a dict / list / scalar tree."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()  # numpy arrays and scalars
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key_entry(k)}: {to_yaml(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(to_yaml(v) for v in value) + "]"
    return _scalar(value)
