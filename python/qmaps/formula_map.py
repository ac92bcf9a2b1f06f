"""qmaps.Map: a map written as formulas (docs/formulas.md), the [map] table of a configuration."""
from . import toml_text
from .errors import ConfigError

_TEXTS = ("step", "equations", "momentum", "start", "invariants", "continuous")


class Map(dict):
    """A map written as formulas: the [map] table it stands for, so that it goes where a [map]
    table goes: qmaps.run({"map": qmaps.Map(...), "ensemble": {...}, ...}).

    name        the map's name
    form        "phase" or "two_step"
    parameters  {name: default} (each a number)
    step, equations, momentum, start, invariants, continuous
                the formulas, each a string of assignments (newlines or ';' between them)
    **values    parameters' values for this run, beside their defaults

        kick = qmaps.Map("standard", "phase", {"K": 0.9},
                         step="p1 = p1 - K*sin(q1); q1 = q1 + p1", K=1.2)

    The engine checks the formulas when the run is made: an error is a ConfigError naming the
    key, the line and the column."""

    def __init__(self, name, form, parameters=None, *, step=None, equations=None, momentum=None,
                 start=None, invariants=None, continuous=None, **values):
        super().__init__(name=str(name), form=str(form))
        given = dict(step=step, equations=equations, momentum=momentum, start=start,
                     invariants=invariants, continuous=continuous)
        if parameters:
            if not isinstance(parameters, dict):
                raise ConfigError("qmaps.Map: parameters is a dict {name: default}")
            self["parameters"] = "; ".join(
                f"{k} = {toml_text.value(v, f'parameters[{k!r}]')}" for k, v in parameters.items())
        for key in _TEXTS:
            text = given[key]
            if text is None:
                continue
            if not isinstance(text, str):
                raise ConfigError(f"qmaps.Map: {key} is a string of formulas, not "
                                  f"{type(text).__name__}")
            self[key] = text
        for k, v in values.items():
            if k in self:
                raise ConfigError(f"qmaps.Map: {k!r} is a key of the map, not a parameter")
            toml_text.value(v, k)  # a number, or a ConfigError naming it
            self[k] = v

    def __repr__(self):
        return f"qmaps.Map({self['name']!r}, {self['form']!r})"
