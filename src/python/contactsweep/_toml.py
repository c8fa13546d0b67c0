"""A dict shaped like a spec, written as TOML text for the engine's parser.

Top-level values come first, then one [section] per top-level dict; deeper dicts are inline
tables. Keys keep their insertion order: the order of the grid axes is the order of the grid
(first axis slowest), as in a spec file.
"""
import json
import math
import numbers
import re
from collections.abc import Mapping

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+\Z")


def key(name):
    name = str(name)
    return name if _BARE_KEY.match(name) else string(name)


def string(text):
    # JSON's escapes are TOML's (\" \\ \n \uXXXX); TOML also wants DEL escaped.
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def value(v):
    """One TOML value: the text after `key = `."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        x = float(v)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return float.__repr__(x)  # the shortest text that reads back to the same double
    if isinstance(v, str):
        return string(v)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }"
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return value(v.tolist())
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    raise ValueError(f"spec: {v!r} ({type(v).__name__}) has no TOML form")


def dumps(spec):
    if not isinstance(spec, Mapping):
        raise ValueError(f"spec: expected a dict of sections, got {type(spec).__name__}")
    lines = [f"{key(k)} = {value(v)}" for k, v in spec.items() if not isinstance(v, Mapping)]
    for name, section in spec.items():
        if isinstance(section, Mapping):
            lines.append(f"[{key(name)}]")
            lines += [f"{key(k)} = {value(v)}" for k, v in section.items()]
    return "\n".join(lines) + "\n"
