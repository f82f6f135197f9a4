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
    pandas.DataFrame(cols)

Units are SI (kg, m, s, rad); quaternions are Hamilton, scalar first (w, x, y, z); H_B is
the total angular momentum about the system centre of mass in body components.
Bad input raises ValueError with the CLI's one-line message ("<source>: <key> = <value>:
<rule>"); files that cannot be read raise RuntimeError. Ctrl-C stops a run or a sweep
with KeyboardInterrupt.
"""

import os as _os

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
    "trajectory_columns",
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

class SimulationResult:
    """The result of simulate(): the trajectory on the output grid and its analysis.

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
      events             dict of columns: the hinge event table (/events/hinge/*): time [s],
                         panel, panel_name, kind, angle [rad], rate_before, rate_after
                         [rad/s], impulse [N m s], w_jump_B (E, 3) [rad/s],
                         energy_dissipated [J], drive_work [J]
      latch_times        (P,) or (0,) [s] per panel, NaN if it never locked
      danger_windows     dict t_begin, t_end [s]
    Analysis:
      stages             list of dicts, one per stage (hinge profiles: per phase): index,
                         name, law, from, to, t_begin [s], t_end [s], rigid, moments_end
                         [kg m^2], spin_axis_role, regime, one_minus_k2,
                         separatrix_distance, predicted_flip_half_period [s],
                         predicted_flips [s], observed_flips [s], predicted_flip_count,
                         observed_flip_count, max_flip_time_difference [s], caveat,
                         rigid_body_only
      stage_table        the same as a dict of columns (pandas.DataFrame(r.stage_table))
      statistics         dict steps, rejected, evaluations, dense_steps
      termination, reached_end, message, max_h_N_drift, wall_seconds [s],
      energy_initial, energy_final [J], max_spin_axis_angle [rad], panel_names,
      spin_axis_B, profile (the Profile as run)
    """

    def __init__(self, raw):
        for k, v in raw.pop("trajectory").items():  # one per trajectory_columns() entry
            setattr(self, k, v)
        self.flips = raw.pop("flip_times")
        self.predicted_flips = raw.pop("predicted_flip_times")
        self.events = raw.pop("hinge_events")
        for k, v in raw.items():
            setattr(self, k, v)

    @property
    def stage_table(self):
        """The stages as a dict of columns (pandas.DataFrame(result.stage_table))."""
        keys = list(self.stages[0].keys()) if self.stages else []
        return {k: [s[k] for s in self.stages] for k in keys}

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


def simulate(profile, method=None, rtol=None, atol=None, step=None, dt=None, coupling=None,
             mode=None, progress=None):
    """Run a deployment profile; returns a SimulationResult (numpy arrays, stage analysis).

    profile : a Profile, a profile file's path, or a dict (profile_from_dict)
    method  : integrator (deploysim.methods()), as ``--method``
    rtol    : relative tolerance; atol: absolute tolerance relative to |H_B(0)|
    step    : fixed step [s] (initial step of adaptive methods)
    dt      : output sampling interval [s]
    coupling: 'quasi-rigid' | 'exact'; mode: 'tensor' | 'geometry'
    progress: optional callable(fraction) called with the fraction done in [0, 1]

    The run is ``deploysim simulate``'s (analysis::RunMission): with the same settings its
    arrays equal the HDF5 file's bit for bit. The GIL is released while it runs (other
    Python threads go on; two simulate calls in two threads use two cores). Ctrl-C raises
    KeyboardInterrupt. ValueError (the CLI's one-line message) for bad settings;
    RuntimeError if the integration does not reach the end.
    """
    if isinstance(profile, dict):
        profile = profile_from_dict(profile)
    elif not isinstance(profile, Profile):
        profile = load_profile(profile)
    if any(x is not None for x in (method, rtol, atol, step, dt, coupling, mode)):
        profile = profile.with_overrides(method=method, rtol=rtol, atol=atol, step=step, dt=dt,
                                         coupling=coupling, mode=mode)
    raw = _deploysim._simulate(profile, progress)
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
