"""deploysim from Python: spinning spacecraft that deploy their panels (Dzhanibekov effect).

A thin layer over the same C++ library as the ``deploysim`` command (docs/design.md
section 4): the same readers, rules and messages, the same integrators, the same numbers
(bit for bit the arrays ``deploysim simulate`` writes to HDF5). numpy in, numpy out.

    import deploysim
    p = deploysim.load_profile("deployment_profiles/smallsat_spring_deploy.yaml")
    r = deploysim.simulate(p)                 # releases the GIL while it runs
    r.time, r.H_B, r.q_NB, r.hinge_angles     # numpy arrays (units in SimulationResult)
    r.stages                                  # per-stage analysis, a list of dicts
    fb = deploysim.FreeBody([3.036e-6, 2.741e-6, 0.699e-6], [1e-8, 2.1252e-5, 1e-8])
    fb.H_B(numpy.linspace(0, 40, 4001)), fb.flip_times(0, 40), fb.period, fb.regime
    cols = deploysim.run_sweep("sweeps/smallsat_duration_spin.yaml", threads=2)
    pandas.DataFrame(cols), pandas.DataFrame(r.events), r.units["H_B"]
    deploysim.write_h5(r, "run.h5"); deploysim.view("run.h5", "run.html")
    deploysim.report("deployment_profiles/smallsat_spring_deploy.yaml", "report.html")

Units are SI (kg, m, s, rad); quaternions are Hamilton, scalar first (w, x, y, z); H_B is
the total angular momentum about the system centre of mass in body components. Every
table carries its units: ``result.units``, ``result.events.units``, ``result.stage_units``,
``run_sweep(...).units`` map column names to unit strings ("1": dimensionless, "none":
text), the strings of the HDF5 files' ``units`` attributes. Values that do not apply are
None (text) and NaN (numbers), where ``deploysim analyze --json`` writes null.
Bad input raises ValueError with the CLI's one-line message ("<source>: <key> = <value>:
<rule>"); files that cannot be read raise RuntimeError. Ctrl-C stops a run or a sweep
with KeyboardInterrupt.
"""

import json as _json
import os as _os
import shutil as _shutil
import subprocess as _subprocess
import sys as _sys

import numpy as _np

from . import _deploysim
from ._deploysim import FreeBody, Model, Profile, SweepSpec, methods  # noqa: F401
from ._yamltext import to_yaml as _to_yaml

__version__ = _deploysim.__version__
build_id = _deploysim.build_id
HAVE_CROSSCHECK = _deploysim.HAVE_CROSSCHECK

__all__ = [
    "FreeBody", "Model", "Profile", "SweepSpec", "SimulationResult", "methods",
    "load_model", "load_profile", "load_sweep", "model_from_dict", "profile_from_dict",
    "sweep_from_dict", "simulate", "run_sweep", "hardware_threads", "crosscheck",
    "trajectory_columns", "write_h5", "view", "report", "cli_path", "Table",
]


# ---- models and profiles ----

def load_model(path):
    """Read a model file (models/*.yaml, docs/file_formats.md "Models") -> Model.

    ValueError naming the file, key, value and rule for bad content (the CLI's message);
    RuntimeError for a file that cannot be read.
    """
    return _deploysim._load_model(_os.fspath(path))


def load_profile(path):
    """Read a deployment profile (deployment_profiles/*.yaml) and its model -> Profile.

    The same reader and checks as ``deploysim simulate PATH`` (io::LoadProfile): strict
    keys, physical values, the integrator settings. ValueError with the CLI's one-line
    message for bad content; RuntimeError for a file that cannot be read.
    """
    return _deploysim._load_profile(_os.fspath(path))


def model_from_dict(d, source="<dict>"):
    """Build a Model from a dict with the schema of a model file.

    ``source`` names the dict in error messages (where a file's messages name the file):
    ValueError "<source>: <key> = <value>: <rule>", the same rules and messages as files.
    """
    if not isinstance(d, dict):
        raise TypeError("model_from_dict: a dict is needed")
    return _deploysim._model_from_text(_to_yaml(d), source)


def profile_from_dict(d, source="<dict>", base_dir="."):
    """Build a Profile from a dict with the schema of a profile file.

    ``d["model"]`` is a model file (relative to ``base_dir``, as a file's is relative to
    its folder), a Model, or a dict with the model's schema. ``source`` names the dict in
    error messages. The same reader, rules and one-line ValueError messages as
    load_profile (docs/file_formats.md).

    Example:
        profile_from_dict({"name": "spin", "model": "models/wing_nut.yaml",
                           "initial": {"angular_momentum": [1e-8, 2.1252e-5, 1e-8]},
                           "stages": [{"name": "free", "hold": "body", "until": 40}],
                           "integrator": {"method": "exact"}, "output": {"dt": 0.01}})
    """
    if not isinstance(d, dict):
        raise TypeError("profile_from_dict: a dict is needed")
    model = d.get("model")
    given = None
    if isinstance(model, Model):
        given = model
    elif isinstance(model, dict):
        given = model_from_dict(model, source=f"{source} model")
    if given is not None:
        d = dict(d)
        d["model"] = given.name
    return _deploysim._profile_from_text(_to_yaml(d), source, _os.fspath(base_dir), given)


# ---- simulate ----

class Table(dict):
    """A table as a dict of 1-D columns {name: numpy array or list}, one entry per row, so
    that ``pandas.DataFrame(table)`` takes it as it is; ``units`` maps each column name to
    its unit string ("1": dimensionless, "none": text)."""

    def __init__(self, columns, units):
        super().__init__(columns)
        self.units = {k: units[k] for k in self}


class EventTable(Table):
    """The hinge event table (Table). The hinge's jump of the body rate is the three columns
    w_jump_B_x, w_jump_B_y, w_jump_B_z; ``events["w_jump_B"]`` stacks them into the (E, 3)
    array of the HDF5 file's /events/hinge/w_jump_B (not a column: derived on request)."""

    def __missing__(self, key):
        if key == "w_jump_B":
            return _np.stack([self["w_jump_B_x"], self["w_jump_B_y"], self["w_jump_B_z"]],
                             axis=-1).reshape(-1, 3)
        raise KeyError(key)


# The units of the tables that are not trajectory columns: the strings of the `units`
# attributes of the same datasets in the HDF5 file (docs/file_formats.md). The hinge
# events' come from their one table in the library (a vector's three columns _x, _y, _z).
EVENT_UNITS = {
    (c["name"] + s if c["type"] == "vector3" else c["name"]): c["units"]
    for c in _deploysim._hinge_event_columns()
    for s in (("_x", "_y", "_z") if c["type"] == "vector3" else ("",))
}
# The stage table's and the danger windows' come from their tables in the library too
# (run::StageTable, with the stage's flip lists; run::DangerWindowTable).
STAGE_UNITS = {c["name"]: c["units"] for c in _deploysim._stage_columns()}
STAGE_UNITS.update({"predicted_flips": "s", "observed_flips": "s"})
WINDOW_UNITS = {c["name"]: c["units"] for c in _deploysim._danger_window_columns()}
_RESULT_UNITS = {
    "flips": "s", "predicted_flips": "s", "spin_axis_45_times": "s", "latch_times": "s",
    "max_h_N_drift": "1", "wall_seconds": "s", "energy_initial": "J", "energy_final": "J",
    "max_spin_axis_angle": "rad", "final_time": "s", "final_J_B": "kg m^2", "spin_axis_B": "1",
}


class SimulationResult:
    """The result of simulate(): the trajectory on the output grid and its analysis.

    ``units`` maps every array and number below to its unit string (the trajectory's from
    trajectory_columns(), e.g. units["H_B"] == "kg m^2/s"; "1" dimensionless).
    Arrays (N output times; P panels, 0 unless geometry mode), the datasets of
    ``deploysim simulate``'s HDF5 file (docs/file_formats.md), bit for bit:
      time               (N,)      [s]
      H_B                (N, 3)    [kg m^2/s] total angular momentum about the system CoM, B
      w_NB_B             (N, 3)    [rad/s] body angular velocity, B components
      q_NB               (N, 4)    attitude, Hamilton, scalar first (w, x, y, z); R_NB: B -> N
      J_B                (N, 3, 3) [kg m^2] inertia about the system CoM, B
      principal_moments  (N, 3)    [kg m^2] eigenvalues of J_B, ascending
      h_rel_B            (N, 3)    [kg m^2/s] relative momentum of the panels
      h_N                (N, 3)    [kg m^2/s] inertial momentum (constant)
      energy             (N,)      [J] total kinetic energy about the system CoM
      energy_rigid       (N,)      [J] its rigid-body part 1/2 w.J_B w
      energy_spring      (N,)      [J] stored in free hinges' springs (0 for stage profiles)
      energy_total       (N,)      [J] energy + energy_spring
      euler_313          (N, 3)    [rad] precession, nutation, spin relative to h_N
      spin_axis_angle    (N,)      [rad] initial body spin axis vs h_N
      hinge_angles       (N, P)    [rad]; hinge_rates (N, P) [rad/s]
      work_damper , work_friction , work_motor , work_drive , work_impacts (N,) [J] the
                         energy ledger: work done on the system since the start by each
                         source; energy_total = energy_total[0] + their sum
    Events:
      flips              (F,)      [s] located flips (/events/flip_time)
      predicted_flips    (F',)     [s] closed-form flips of the rigid stages
      spin_axis_45_times (C,)      [s] 45-degree crossings (hinge profiles)
      events             the hinge event table (/events/hinge/*), a Table of 1-D columns
                         (pandas.DataFrame(r.events)) with .units: time [s], panel,
                         panel_name, kind, angle [rad], rate_before, rate_after [rad/s],
                         impulse [N m s], w_jump_B_x, w_jump_B_y, w_jump_B_z [rad/s],
                         energy_dissipated [J], drive_work [J]; r.events["w_jump_B"] is
                         the (E, 3) stack of the three w_jump_B columns
      latch_times        (P,) or (0,) [s] per panel, NaN if it never locked
      danger_windows     Table t_begin, t_end [s]
    Analysis:
      stages             list of dicts, one per stage (hinge profiles: per phase): index,
                         name, law, from, to, t_begin [s], t_end [s], rigid, moments_end
                         [kg m^2], spin_axis_role, regime, one_minus_k2,
                         separatrix_distance, predicted_flip_half_period [s],
                         predicted_flips [s], observed_flips [s], predicted_flip_count,
                         observed_flip_count, max_flip_time_difference [s], caveat,
                         rigid_body_only. Not applicable: from, to None for a hinge
                         profile's phases; regime None, one_minus_k2 and
                         predicted_flip_half_period NaN for stages that are not rigid
                         (+inf half period: a rigid stage that predicts no flips)
      stage_table        the same as a Table (pandas.DataFrame(r.stage_table))
      stage_units        units of the stage dicts' keys
      statistics         dict steps, rejected, evaluations, dense_steps
      termination, reached_end, message, max_h_N_drift, wall_seconds [s],
      energy_initial, energy_final [J], max_spin_axis_angle [rad], panel_names,
      spin_axis_B, profile (the Profile as run)
      outcome            the verdict measured from the motion, a dict: the HDF5 file's
                         @outcome (docs/file_formats.md, "The outcome"); outcome["headline"]
                         is the sentence the CLI prints after "verdict: " (None where JSON
                         has null)
      warnings           list of one-line strings: the profile's legal but almost certainly
                         unmeant inputs (docs/file_formats.md, "Warnings"), as the CLI prints
      body               a hinged model's body as the run moved it, a dict: the HDF5 file's
                         @body (docs/file_formats.md, "The body"): hub, panels (the
                         appendages' generated ones included), appendages; None for a
                         tensors model
      appendages         body["appendages"] (empty list without a body): per flexible
                         appendage name, kind, root, hinges, stiffness, damping, segments,
                         planes, damping_ratio, chain_frequencies, beam_frequencies
    """

    stage_units = STAGE_UNITS

    def __init__(self, raw):
        self.units = {}
        for k, v in raw.pop("trajectory").items():  # one per trajectory_columns() entry
            setattr(self, k, v)
        self.units.update((c["name"], c["units"]) for c in trajectory_columns())
        self.flips = raw.pop("flip_times")
        self.predicted_flips = raw.pop("predicted_flip_times")
        columns = {}
        for k, v in raw.pop("hinge_events").items():  # a vector: three columns in its place
            if isinstance(v, _np.ndarray) and v.ndim == 2:
                for i, c in enumerate("xyz"):
                    columns[f"{k}_{c}"] = _np.ascontiguousarray(v[:, i])
            else:
                columns[k] = v
        self.events = EventTable(columns, EVENT_UNITS)
        self.danger_windows = Table(raw.pop("danger_windows"), WINDOW_UNITS)
        self.outcome = _json.loads(raw.pop("outcome_json"))
        body = raw.pop("body_json")
        self.body = None if body is None else _json.loads(body)
        self.appendages = [] if self.body is None else self.body["appendages"]
        for k, v in raw.items():
            setattr(self, k, v)
        self.units.update(_RESULT_UNITS)

    @property
    def stage_table(self):
        """The stages as a Table of columns (pandas.DataFrame(result.stage_table))."""
        keys = list(self.stages[0].keys()) if self.stages else list(STAGE_UNITS)
        return Table({k: [s[k] for s in self.stages] for k in keys}, STAGE_UNITS)

    def __len__(self):
        return len(self.time)

    def __repr__(self):
        return (f"<deploysim.SimulationResult '{self.profile.name}': {len(self.time)} samples "
                f"{self.time[0] if len(self.time) else 0:g}..{self.final_time:g} s, "
                f"{len(self.flips)} flips, {self.termination}>")


def trajectory_columns():
    """The trajectory's columns, as the HDF5 file, the CSV and SimulationResult hold them:
    a list of dicts name, units, shape ('scalar', 'vector3', 'quaternion' (w, x, y, z),
    'matrix3', 'per-panel'), description and derived (computed from other columns)."""
    return _deploysim._trajectory_columns()


def _as_profile(profile):
    if isinstance(profile, dict):
        return profile_from_dict(profile)
    if isinstance(profile, Profile):
        return profile
    return load_profile(profile)


def _refuse_output_over_inputs(output, profile, csv):
    """As the CLI: an output that names the profile or model file is refused (ValueError)."""
    targets = [_os.fspath(output)] + ([_os.fspath(output) + ".csv"] if csv else [])
    for t in targets:
        for src in (profile.source, profile.model.source):
            if _os.path.exists(src) and _os.path.exists(t) and _os.path.samefile(src, t):
                raise ValueError(f"{t}: is an input of the run (rule: outputs never "
                                 f"overwrite their inputs)")


def simulate(profile, method=None, rtol=None, atol=None, step=None, dt=None, coupling=None,
             mode=None, progress=None, output=None, csv=False, until=None):
    """Run a deployment profile; returns a SimulationResult (numpy arrays, stage analysis).

    profile : a Profile, a profile file's path, or a dict (profile_from_dict)
    method  : integrator (deploysim.methods()), as ``--method``
    rtol    : relative tolerance; atol: absolute tolerance relative to |H_B(0)|
    step    : fixed step [s] (initial step of adaptive methods)
    dt      : output sampling interval [s]
    coupling: 'quasi-rigid' | 'exact'; mode: 'tensor' | 'geometry'
    until   : end the run at this time [s], as ``--until`` (a stage profile: in a hold
              stage, at a stage end, or held past its last stage)
    progress: optional callable(fraction) called with the fraction done in [0, 1]
    output  : optional trajectory file (HDF5) written during the same run, the file of
              ``deploysim simulate -o OUTPUT``; csv=True also writes OUTPUT.csv. Written
              atomically, and only when the run reaches its end.

    The run is ``deploysim simulate``'s (run::RunMission): with the same settings its
    arrays equal the HDF5 file's bit for bit. The GIL is released while it runs (other
    Python threads go on; two simulate calls in two threads use two cores). Ctrl-C raises
    KeyboardInterrupt. ValueError (the CLI's one-line message) for bad settings;
    RuntimeError if the integration does not reach the end.
    """
    profile = _as_profile(profile)
    if any(x is not None for x in (method, rtol, atol, step, dt, coupling, mode, until)):
        profile = profile.with_overrides(method=method, rtol=rtol, atol=atol, step=step, dt=dt,
                                         coupling=coupling, mode=mode, until=until)
    if output is not None:
        _refuse_output_over_inputs(output, profile, csv)
    raw = _deploysim._simulate(profile, progress,
                               _os.fspath(output) if output is not None else "", bool(csv))
    result = SimulationResult(raw)
    if not result.reached_end:
        raise RuntimeError(f"{profile.source}: integration {result.message}")
    return result


# ---- sweeps ----

def load_sweep(path):
    """Read a sweep file (sweeps/*.yaml, docs/sweeps.md) and its base profile -> SweepSpec.

    Every case is built once to check it (as ``deploysim sweep`` does before running).
    ValueError with the CLI's one-line message for bad content.
    """
    return _deploysim._load_sweep(_os.fspath(path))


def sweep_from_dict(d, source="<dict>", base_dir="."):
    """Build a SweepSpec from a dict with the schema of a sweep file (docs/sweeps.md).

    ``d["base"]`` is a profile file (relative to ``base_dir``), a Profile or a profile
    dict. Same rules and messages as load_sweep, naming ``source``.
    """
    if not isinstance(d, dict):
        raise TypeError("sweep_from_dict: a dict is needed")
    base = d.get("base")
    given = None
    if isinstance(base, Profile):
        given = base
    elif isinstance(base, dict):
        given = profile_from_dict(base, source=f"{source} base", base_dir=base_dir)
    if given is not None:
        d = dict(d)
        d["base"] = given.name
    return _deploysim._sweep_from_text(_to_yaml(d), source, _os.fspath(base_dir), given)


class SweepResults(dict):
    """The sweep's results table: a dict {column name: numpy array}, one row per case, in
    the column order of the results file (docs/sweeps.md, "Results file"), so that
    ``pandas.DataFrame(results)`` takes it as it is. Also:
      units, roles, descriptions   dicts by column name
      run_time                     (N,) [s] wall time per case (not deterministic)
      wall_seconds, threads        the run
    """


def run_sweep(sweep, threads=0, progress=None, output=None, csv=False):
    """Run a sweep; returns SweepResults (a dict of numpy columns for pandas.DataFrame).

    sweep   : a SweepSpec, a sweep file's path, or a dict (sweep_from_dict)
    threads : worker threads (0: all hardware threads)
    progress: optional callable(done, total), called from the calling thread about every
              0.1 s and once at the end
    output  : optional results file (HDF5, as ``deploysim sweep -o``), written atomically
              once the sweep is complete; csv=True also writes OUTPUT.csv

    The cases run on the CLI's thread pool with the GIL released; each case's outcome is
    the CLI's, bit for bit, whatever the thread count. Ctrl-C raises KeyboardInterrupt
    after the cases at hand finish; nothing is written then.
    """
    if isinstance(sweep, dict):
        sweep = sweep_from_dict(sweep)
    elif not isinstance(sweep, SweepSpec):
        sweep = load_sweep(sweep)
    raw = _deploysim._run_sweep(sweep, int(threads), progress,
                                _os.fspath(output) if output is not None else "", bool(csv))
    out = SweepResults(raw["columns"])
    for k in ("units", "roles", "descriptions", "run_time", "wall_seconds", "threads"):
        setattr(out, k, raw[k])
    return out


def hardware_threads():
    """Worker threads a sweep uses by default (the hardware threads)."""
    return _deploysim.hardware_threads()


# ---- cross-check ----

def crosscheck(profile, accuracy=None, until=None, dt=None, own_error=0.0):
    """The Simbody cross-check (``deploysim crosscheck``) where the module has it.

    profile : Profile, path or dict; accuracy: Simbody RK-Merson accuracy (default 1e-12;
    1e-14 for hinge profiles); until: stop time [s]; dt: output interval [s];
    own_error: hinge profiles, also run Simbody at this looser accuracy.
    Returns a dict: time [s]; reduced and simbody dicts of H_B, h_N [kg m^2/s], w_NB_B
    [rad/s], q_NB (w, x, y, z), flip_time [s]; difference dict H_B_relative [1],
    attitude [rad], w_NB_B [rad/s]; the maxima and Simbody's own momentum drift.
    RuntimeError when this build has no Simbody (HAVE_CROSSCHECK False).
    """
    if not HAVE_CROSSCHECK:
        raise RuntimeError("deploysim was built without the Simbody cross-check")
    if isinstance(profile, dict):
        profile = profile_from_dict(profile)
    elif not isinstance(profile, Profile):
        profile = load_profile(profile)
    return _deploysim._crosscheck(profile, accuracy, until, dt, float(own_error))


# ---- files, the 3D viewer and the mission report ----

def write_h5(run, path, csv=False, progress=None):
    """Write the trajectory file (HDF5) of ``deploysim simulate -o PATH``; returns PATH.

    run : a SimulationResult, a Profile, a profile file's path or a profile dict. The
          package keeps no file writer's state in a result: for a SimulationResult the
          profile it ran (``run.profile``, with its overrides) is run again straight into
          the file; the run is deterministic, so the file holds the result's arrays bit for
          bit. To write the file without a second run, pass ``output=`` to simulate().
    csv : also write PATH.csv (``--csv``).
    """
    profile = run.profile if isinstance(run, SimulationResult) else run
    simulate(profile, progress=progress, output=path, csv=csv)
    return path


def cli_path():
    """The ``deploysim`` command the package runs for view() and report(): the first of
    $DEPLOYSIM_BIN, the copy installed with the package (``pip install .`` puts the command
    and its Python tools in deploysim/_cli/; a CMake build links its own there) and
    ``deploysim`` on PATH. RuntimeError saying how to get one when there is none."""
    here = _os.path.dirname(_os.path.abspath(__file__))
    candidates = [_os.environ.get("DEPLOYSIM_BIN"),
                  _os.path.join(here, "_cli", "bin", "deploysim"),
                  _shutil.which("deploysim")]
    for c in candidates:
        if c and _os.path.isfile(c) and _os.access(c, _os.X_OK):
            return c
    raise RuntimeError(
        "deploysim: no deploysim command found for the viewer and the report (looked at "
        "$DEPLOYSIM_BIN, " + _os.path.join(here, "_cli", "bin", "deploysim") + " and PATH). "
        "`pip install .` of the source tree installs it with the package; in a CMake build, "
        "build the `deploysim` target; or set DEPLOYSIM_BIN to a deploysim executable "
        "(its tools/ must be installed beside it or in the source tree it was built from)")


def _run_tool(args):
    env = dict(_os.environ)
    # The tools run with this interpreter (its numpy, h5py, matplotlib), unless the caller
    # chose another.
    env.setdefault("DEPLOYSIM_PYTHON", _sys.executable)
    p = _subprocess.run([cli_path(), *args], stdout=_subprocess.PIPE, stderr=_subprocess.PIPE,
                        text=True, env=env)
    if p.returncode != 0:
        lines = [x for x in p.stderr.strip().splitlines() if x.strip()]
        msg = lines[-1] if lines else f"exit status {p.returncode}"
        raise RuntimeError(f"deploysim {args[0]}: {msg}")
    return p


def view(h5, html, model=None, title=None):
    """Write the self-contained 3D viewer page (one HTML file) of a trajectory or
    cross-check file: ``deploysim view H5 -o HTML`` (tools/view.py, docs/viewer.md).
    Returns HTML. RuntimeError with the tool's one-line message on failure (nothing is
    written then), or when no deploysim command is found (cli_path())."""
    args = ["view", _os.fspath(h5), "-o", _os.fspath(html)]
    if model is not None:
        args += ["--model", _os.fspath(model)]
    if title is not None:
        args += ["--title", str(title)]
    _run_tool(args)
    return html


def report(profile, html, method=None, rtol=None, atol=None, step=None, dt=None):
    """Write the mission report of a profile file (one self-contained HTML file):
    ``deploysim report PROFILE -o HTML`` (tools/report.py), which runs the profile itself.

    profile : a profile file's path (the report quotes and runs the file; a Profile or a
              dict has none); method, rtol, atol, step [s], dt [s]: as simulate's.
    Returns HTML. RuntimeError with the tool's one-line message on failure (nothing is
    written then), or when no deploysim command is found (cli_path())."""
    if isinstance(profile, (Profile, dict)):
        raise TypeError("report: a profile file's path is needed (the report runs and quotes "
                        "the file)")
    args = ["report", _os.fspath(profile), "-o", _os.fspath(html), "--quiet"]
    for name, v in (("method", method), ("rtol", rtol), ("atol", atol), ("step", step),
                    ("dt", dt)):
        if v is not None:
            args += [f"--{name}", repr(v) if isinstance(v, float) else str(v)]
    _run_tool(args)
    return html
