"""qmaps.Map: a map written as formulas (docs/formulas.md), the [map] table of a configuration."""
from . import toml_text
from .errors import ConfigError

_TEXTS = ("step", "equations", "momentum", "start", "invariants", "continuous")


class Map(dict):
    """A map written as formulas (docs/formulas.md): a dict, the ``[map]`` table it stands for,
    so that it goes where a ``[map]`` table goes, as in ``qmaps.run({"map": qmaps.Map(...),
    ...})``, and where a map's name goes in ``qmaps.orbit`` and ``qmaps.integrability``.

    The formulas are each a string of assignments, newlines or ";" between them. The engine
    checks them when the run is made: an error is a ConfigError naming the key, the line and the
    column.

    Args:
        name: the map's name in the file and in messages (letters, digits, "_", "-").
        form: "phase" (the state is the phase point) or "two_step" (the state is q_n, q_{n+1}).
        parameters: ``{name: default}``, each default a number.
        step: the step: the new q1, q2, p1, p2 (phase form), or q1_next, q2_next (two-step).
        equations: two-step form only, instead of ``step``: eq1 and eq2, equations linear in
            q1_next, q2_next.
        momentum: two-step form only: p1, p2 at node n (default ``(q_next - q)/h``).
        start: two-step form only: the first q1_next, q2_next from q1, q2, p1, p2 (default
            ``q + h p``).
        invariants: each name assigned is an invariant, in order, but names starting with "_".
        continuous: A, B, alpha, beta, delta of the quartic Hamiltonian the map discretizes.
        **values: the parameters' values for this run, beside their defaults.

    Raises:
        ConfigError: parameters that are not a dict, a formula that is not a string, or a
            value that names a key of the map or is not a bool, number, string or list.

    Example::

        kick = qmaps.Map("standard", "phase", {"K": 0.9},
                         step="p1 = p1 - K*sin(q1); q1 = q1 + p1", K=1.2)
        table = qmaps.orbit(kick, ic=(0.5, 0.0, 0.2, 0.0), steps=100, frame=False)
    """

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
