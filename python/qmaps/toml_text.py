"""TOML text of a configuration given as a dict, for the engine's parser: tables for dicts,
arrays of tables for lists of dicts ([[section]]), and values that read back exactly (floats by
repr, the shortest text that does)."""
import math
import numbers

from .errors import ConfigError


def value(v, key="a configuration value"):
    """One TOML value; `key` names it in a ConfigError."""
    if hasattr(v, "tolist") and not isinstance(v, str):  # numpy: 0-d arrays and scalars too
        return value(v.tolist(), key)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        if not -2**63 <= v < 2**63:
            raise ConfigError(f"{key} = {v}: an integer must lie in TOML's 64 bits, "
                              "-2**63 to 2**63 - 1")
        return str(int(v))
    if isinstance(v, numbers.Real):
        x = float(v)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        text = repr(x)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(v, str):
        escaped = v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        return f'"{escaped}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x, key) for x in v) + "]"
    raise ConfigError(f"{key} = {v!r}: a configuration value must be a bool, number, string or "
                      f"list, not {type(v).__name__}")


def _key(k):
    k = str(k)
    return k if k and all(c.isalnum() or c in "_-" for c in k) else value(k)


def _table(d, prefix, lines):
    tables = []
    for k, v in d.items():
        if isinstance(v, dict) or (isinstance(v, (list, tuple)) and v and
                                   all(isinstance(x, dict) for x in v)):
            tables.append((k, v))
        else:
            lines.append(f"{_key(k)} = {value(v, f'{prefix}.{k}' if prefix else str(k))}")
    for k, v in tables:
        name = f"{prefix}.{_key(k)}" if prefix else _key(k)
        if isinstance(v, dict):
            lines.append(f"\n[{name}]")
            _table(v, name, lines)
        else:
            for item in v:
                lines.append(f"\n[[{name}]]")
                _table(item, name, lines)


def dumps(config):
    """The TOML text of `config`, a dict of tables."""
    if not isinstance(config, dict):
        raise TypeError(f"a configuration is a dict, TOML text or a path, not {type(config).__name__}")
    lines = []
    _table(config, "", lines)
    return "\n".join(lines).lstrip("\n") + "\n"
