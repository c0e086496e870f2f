"""The EHL point-contact workbench from Python.

The same scenes, solvers and files as the ``ehl`` command line, with the answers as Python
objects: standard observables with their units, fields as numpy arrays in SI with shape
``(ny, nx)`` on the axes ``x``, ``y`` [m], histories of marching runs as arrays, the comparison
table as rows a ``pandas.DataFrame`` takes as they are.

    import ehl
    c = ehl.compare("seed", grid=129)
    print(c)                      # the table the command line prints
    rows = c.table()              # list of dicts: pandas.DataFrame(rows)
    p = c["reynolds"].fields["pressure_pa"]

Every answer carries its estimated discretisation error (the same model on half and a quarter
of the points per side): ``Result.errors``, and ``± error`` in the printed table. An answer whose
error is beyond the limit (5 %, or the ``accuracy`` asked), or whose film went below zero,
is flagged: ``Result.flags`` lists why, and an :class:`AccuracyWarning` says so. Ask for an
accuracy instead of a grid with ``accuracy=0.02``: the grid then follows the accuracy rule.

Errors: a refused scene or sweep raises :class:`SceneError` (``.field``, ``.value``,
``.allowed``); a model that does not converge raises :class:`ModelError` from :func:`run` (its
message is the solver's diagnosis), and in :func:`compare` is listed in the table with its
diagnosis (``Comparison.errors``), as on the command line. Solves run with the GIL released;
Ctrl-C stops the solve (within about a second: the solvers check between cycles and steps,
and nothing is written) and raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import csv
import json
import os
import warnings
from typing import Any

import numpy as np

from . import _ehl
from ._ehl import ModelError, SceneError

__all__ = [
    "Scene",
    "Result",
    "Comparison",
    "SweepResult",
    "Table",
    "SceneError",
    "ModelError",
    "AccuracyWarning",
    "scene",
    "run",
    "compare",
    "sweep",
    "builtins",
]


class AccuracyWarning(UserWarning):
    """An answer whose estimated error is beyond the limit (5 %, or the accuracy asked), whose
    film went below zero, or whose error could not be estimated: ``Result.flags`` says which."""


class Scene:
    """A checked scene: a built-in name, a JSON file's path, or a dict, with every default filled."""

    def __init__(
        self,
        spec: str | os.PathLike | dict[str, Any] | Scene,
        grid: int | None = None,
        for_compare: bool = False,
    ):
        """``for_compare``: a one-model scene that names its comparison (``comparison``) is that
        comparison, as ``ehl compare NAME`` runs it (``grid`` applies to the comparison)."""
        if isinstance(spec, Scene):
            text, is_json = spec.json, True
        elif isinstance(spec, dict):
            text, is_json = json.dumps(spec), True
        else:
            text, is_json = os.fspath(spec), False
        self.json: str = _ehl.load_scene(text, is_json, grid, bool(for_compare))
        self.data: dict[str, Any] = json.loads(self.json)

    @property
    def name(self) -> str:
        return self.data["name"]

    @property
    def models(self) -> list[str]:
        """The models it runs: one, or a comparison's list."""
        return [self.data["model"]] if self.data.get("model") else list(self.data.get("models", []))

    def to_dict(self) -> dict[str, Any]:
        return json.loads(self.json)

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, models={self.models})"


def scene(spec: str | os.PathLike | dict[str, Any] | Scene, grid: int | None = None) -> Scene:
    """A checked scene from a built-in name, a path or a dict; ``grid`` sets the points per side."""
    return Scene(spec, grid)


def _with_accuracy(s: Scene, accuracy: float | None) -> Scene:
    """``s`` asking for the relative ``accuracy`` (checked), or ``s`` itself."""
    if accuracy is None:
        return s
    d = s.to_dict()
    d["accuracy"] = float(accuracy)
    return Scene(d)


class Result:
    """One model's answer.

    ``observables``: the standard observables, ``{name: (value, unit)}`` (central and minimum film,
    maximum pressure, contact extents, load error, SI). ``pressure`` [Pa] and ``film`` [m]: the
    two fields every model defines, arrays ``(ny, nx)`` on ``x``, ``y`` [m]; ``fields``: every
    field the model writes, ``{name: array (ny, nx)}``, SI (units in the names). ``history``: for
    a marching run, ``{column: array}`` (times and the model's quantities, SI, units in the
    names), else ``None``. ``summary``: the ``summary.json``
    the command line writes. ``report``: the text it prints. ``errors``: each standard
    observable's estimated discretisation error, ``{name: (value, error, unit)}`` (``error``
    ``None`` where none was estimated). ``flags``: why the answer is flagged (an error beyond
    the limit, with the grid that would meet it; a film below zero; an error not estimated),
    empty when it is not; ``flagged``: whether it is. ``caveat``: the flags and any solver
    caveat in one line (a steady solve that settled on a cycle), else ``None``.
    ``solid_contact``: where the solids touch, apart from the fluid, ``{"load_share": share,
    "area_m2": m², "max_pressure_pa": Pa}`` (zeros where a film separates them everywhere),
    or ``None`` for a model that does not say. ``passage``: a march through a patterned
    relief (waviness, roughness): its last passage, ``{"central_film_mean_m", "central_film_min_m",
    "central_film_max_m", "minimum_film_m", "max_pressure_pa", "lambda", "deformed_amplitude_m",
    "amplitude_ratio", "contact_load_share_mean", "contact_load_share_max",
    "contact_area_mean_m2"}`` (the wave's two and the solids' three ``None`` where they do not
    apply), else ``None``. ``passage_errors``: their estimated errors from the coarser grids'
    passages, ``{"central_film_mean_m", "contact_load_share_mean", "contact_area_mean_m2",
    "amplitude_ratio"}`` (each ``None`` where none was estimated), with a passage, else ``None``.
    """

    def __init__(self, raw: dict[str, Any]):
        self.summary: dict[str, Any] = json.loads(raw["summary"])
        sc = self.summary.get("solid_contact")
        self.solid_contact: dict[str, float] | None = (
            {
                "load_share": sc["load_share"],
                "area_m2": sc["area"]["value"],
                "max_pressure_pa": sc["max_pressure"]["value"],
            }
            if sc
            else None
        )
        ps = self.summary.get("passage")
        self.passage: dict[str, float | None] | None = (
            {
                "central_film_mean_m": ps["central_film"]["mean"],
                "central_film_min_m": ps["central_film"]["min"],
                "central_film_max_m": ps["central_film"]["max"],
                "minimum_film_m": ps["minimum_film"]["value"],
                "max_pressure_pa": ps["max_pressure"]["value"],
                "lambda": ps["lambda"],
                "deformed_amplitude_m": (ps["deformed_amplitude"] or {}).get("value"),
                "amplitude_ratio": ps["amplitude_ratio"],
                "contact_load_share_mean": (ps.get("contact_load_share") or {}).get("mean"),
                "contact_load_share_max": (ps.get("contact_load_share") or {}).get("max"),
                "contact_area_mean_m2": (ps.get("contact_area_mean") or {}).get("value"),
            }
            if ps
            else None
        )
        pe = (self.summary.get("accuracy") or {}).get("passage") or {}
        self.passage_errors: dict[str, float | None] | None = (
            {
                "central_film_mean_m": (pe.get("central_film_mean") or {}).get("error"),
                "contact_load_share_mean": (pe.get("contact_load_share_mean") or {}).get("error"),
                "contact_area_mean_m2": (pe.get("contact_area_mean") or {}).get("error"),
                "amplitude_ratio": (pe.get("amplitude_ratio") or {}).get("error"),
            }
            if ps
            else None
        )
        self.report: str = raw["report"]
        self.fields: dict[str, np.ndarray] = dict(raw["fields"])
        self.film: np.ndarray = raw["film"]
        self.pressure: np.ndarray = raw["pressure"]
        self.x: np.ndarray = raw["x"]
        self.y: np.ndarray = raw["y"]
        rows = json.loads(raw["time_series"]) if raw["time_series"] is not None else None
        self.history: dict[str, np.ndarray] | None = _columns(rows) if rows else None
        self.model: str = self.summary.get("model", "")
        self.caveat: str | None = self.summary.get("caveat")
        acc = self.summary.get("accuracy", {})
        self.errors: dict[str, tuple] = {
            k: (v["value"], v["error"], v["unit"]) for k, v in acc.get("observables", {}).items()
        }
        self.flags: list[str] = list(raw.get("flags", []))
        self.flagged: bool = bool(self.flags)

    @property
    def observables(self) -> dict[str, tuple]:
        """``{name: (value, unit)}``, SI; the unit is the name's suffix (``central_film_m``)."""
        return {k: (v, _unit(k)) for k, v in self.summary["observables"].items()}

    def __getitem__(self, name: str) -> Any:
        """An observable's value in SI (``result["central_film_m"]``)."""
        return self.summary["observables"][name]

    def __repr__(self) -> str:
        return self.report


class Comparison:
    """Every model of a comparison scene side by side.

    ``table()``: the rows of ``comparison.json`` (one dict per model), which print as the
    table the command line prints and go into ``pandas.DataFrame`` as they are. ``results``:
    ``{model: Result}`` of the models that converged (each with its ``errors`` and ``flags``);
    ``errors``: ``{model: diagnosis}`` of those that did not. ``comparison``: the whole
    ``comparison.json`` (with ``schedule``, how the models shared the cores, and
    ``total_wall_time_s``).
    """

    def __init__(self, raw: dict[str, Any]):
        self.comparison: dict[str, Any] = json.loads(raw["table"])
        self.text: str = raw["text"]
        self.results: dict[str, Result] = {k: Result(v) for k, v in raw["results"].items()}
        self.errors: dict[str, str] = dict(raw["errors"])

    def table(self) -> Table:
        return Table([dict(r) for r in self.comparison["models"]], self.text)

    @property
    def flagged(self) -> dict[str, list[str]]:
        """``{model: flags}`` of the answers that are flagged."""
        return {k: r.flags for k, r in self.results.items() if r.flags}

    def __getitem__(self, model: str) -> Result:
        if model in self.errors:
            raise ModelError(self.errors[model])
        return self.results[model]

    def __repr__(self) -> str:
        return self.text


class Table(list):
    """Rows (one dict per model) that print as the command line's table: a list, so
    ``pandas.DataFrame(table)`` takes it as it is."""

    def __init__(self, rows: list[dict[str, Any]], text: str):
        super().__init__(rows)
        self.text = text

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return self.text


class SweepResult:
    """A sweep's results: ``table()`` is ``results.csv`` as rows (numbers as floats, ``True``/
    ``False`` as bools, empty cells as ``None``); ``folder`` holds every file the command line
    writes (plan, points, results, charts)."""

    def __init__(self, folder: str, csv_text: str):
        self.folder = folder
        self.csv = csv_text
        self._rows = [{k: _cell(v) for k, v in row.items()} for row in csv.DictReader(csv_text.splitlines())]

    def table(self) -> list[dict[str, Any]]:
        return [dict(r) for r in self._rows]

    def __repr__(self) -> str:
        return f"SweepResult({len(self._rows)} rows in {self.folder})"


def _warn(results: dict[str, Result]) -> None:
    for name, r in results.items():
        if r.flags:
            warnings.warn(f"{name}: " + "; ".join(r.flags), AccuracyWarning, stacklevel=3)


def run(
    spec: str | os.PathLike | dict[str, Any] | Scene,
    grid: int | None = None,
    out: str | os.PathLike | None = None,
    accuracy: float | None = None,
    estimate: bool = True,
) -> Result:
    """Runs a one-model scene; writes the command line's files to ``out`` when given. With
    ``accuracy`` (``0.02``: 2 %) the grid follows the accuracy rule; ``estimate=False`` skips
    the error estimate (the answer then says it was not checked)."""
    s = _with_accuracy(Scene(spec, grid), accuracy)
    if len(s.models) != 1 or not s.data.get("model"):
        raise SceneError(
            f"scene `{s.name}` is a comparison of several models ({', '.join(s.models)}): use ehl.compare"
        )
    r = Result(_ehl.run(s.json, None if out is None else os.fspath(out), bool(estimate)))
    _warn({r.model: r})
    return r


def compare(
    spec: str | os.PathLike | dict[str, Any] | Scene,
    grid: int | None = None,
    out: str | os.PathLike | None = None,
    one_at_a_time: bool = False,
    accuracy: float | None = None,
    estimate: bool = True,
) -> Comparison:
    """Runs every model of a comparison scene on one grid, all at once sharing the cores (or one
    after the other with ``one_at_a_time=True``, so that each wall time is that model's own
    cost); writes the command line's files (``comparison.json``, ``.csv``, each model's folder)
    to ``out`` when given. A one-model scene that names its comparison (the seed's
    ``squeeze-after-stop``: ``stop-compare``) runs that comparison, as the command line does.
    ``accuracy`` and ``estimate`` as for :func:`run`; a flagged answer warns
    (:class:`AccuracyWarning`)."""
    s = _with_accuracy(Scene(spec, grid, for_compare=True), accuracy)
    c = Comparison(
        _ehl.compare_scene(
            s.json, None if out is None else os.fspath(out), bool(one_at_a_time), bool(estimate)
        )
    )
    _warn(c.results)
    return c


def sweep(
    spec: str | os.PathLike | dict[str, Any], out: str | os.PathLike | None = None, jobs: int | None = None
) -> SweepResult:
    """Runs a sweep (a built-in name, a path, or a dict) locally, resumable like the command
    line's, into ``out`` (a new scratch folder when not given)."""
    if isinstance(spec, dict):
        text, is_json = json.dumps(spec), True
    else:
        text, is_json = os.fspath(spec), False
    folder = os.fspath(out) if out is not None else _ehl.scratch_dir()
    path, csv_text = _ehl.run_sweep(text, is_json, folder, jobs)
    return SweepResult(path, csv_text)


def builtins() -> dict[str, list[str]]:
    """The built-in scenes and sweeps by name."""
    scenes, sweeps = _ehl.builtins()
    return {"scenes": list(scenes), "sweeps": list(sweeps)}


def _unit(name: str) -> str:
    for suffix, unit in (("_m", "m"), ("_pa", "Pa"), ("_s", "s"), ("_n", "N")):
        if name.endswith(suffix):
            return unit
    return "1"


def _columns(rows: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    """Rows of nested objects as flat columns (``a.b`` names), each an array."""

    def flat(prefix: str, v: Any, out: dict[str, Any]) -> None:
        if isinstance(v, dict):
            for k, w in v.items():
                flat(f"{prefix}.{k}" if prefix else k, w, out)
        else:
            out[prefix] = v

    cols: dict[str, list[Any]] = {}
    for r in rows:
        f: dict[str, Any] = {}
        flat("", r, f)
        for k, v in f.items():
            cols.setdefault(k, []).append(v)
    return {k: np.asarray(v) for k, v in cols.items()}


def _cell(v: str) -> Any:
    if v == "":
        return None
    if v in ("true", "false"):
        return v == "true"
    try:
        return float(v)
    except ValueError:
        return v
