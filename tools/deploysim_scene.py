#!/usr/bin/python3
"""The scene of a deploysim run, shared by tools/view.py (the 3D HTML viewer) and
tools/animate.py (MP4/GIF): read a trajectory or cross-check file, rebuild the drawn
body from the model and decimate the samples to what the eye needs.

One place for each rule (docs/viewer.md):
- the body is drawn as boxes: a `hinged` model's hub and panels at their hinge angles, as
  the trajectory's @body has them (docs/file_formats.md, "The body": the appendages'
  generated panels included, a beam's segments as thin rods, a slosh bob as a cube, a
  massless link not at all), or the model text's for files written before it
  (docs/design.md 2.5: R_Bk = R_B,parent Rot(a_k, theta_k),
  hinge o_k = o_parent + R_B,parent p_k, CoM o_k + R_Bk r_k), every position relative to the system CoM c(t); an element given by
  `inertia:` instead of `box:` is drawn as its equivalent box; a `tensors` model (or a run in
  tensor mode) as the uniform box with the principal moments of J_B(t) (the mass is only a
  scale: the largest edge is 1);
- the spin axis is that of docs/file_formats.md "Flips" step 1 (the principal axis of
  J_B(t0) nearest H_B(t0), signed along it), fixed in B;
- frames as docs/design.md 1: q_NB (w, x, y, z) maps B components to N components.

Trajectory files are read through tools/deploysim_results.py; cross-check files (another
format) here.
Needs Debian's python3-h5py, python3-numpy, python3-yaml (run with /usr/bin/python3).
"""
import math
import os

import numpy as np

import deploysim_results as results

# Decimation: a sample is kept when, since the last kept one, the body turned by more than
# this angle, a hinge by more than HINGE_STEP, or J_B changed by more than J_STEP (relative),
# or when MAX_GAP of the run has passed (smooth charts on quiet stretches). Between kept
# samples the viewer interpolates (slerp): exact for a turn at a constant rate about a
# fixed axis, the error is the change of the rate over a step (interpolation_error; the
# main job: 0.04 deg).
ROTATION_STEP = math.radians(10.0)
HINGE_STEP = math.radians(1.0)
J_STEP = 0.005
MAX_GAP = 1.0 / 500
# The spin-axis trail shows the last TRAIL_SECONDS of the tip's path (the viewer's default,
# fading with age; the animation's): a whole run's trail fills a hemisphere. A run that
# flips faster keeps two flip intervals (trail_seconds).
TRAIL_SECONDS = 60.0
# A hinge moves between two samples when its angle changes by more than this [rad].
HINGE_MOTION = 1e-9
# analysis::kDegenerateMoments: two principal moments closer than this (relative to the
# largest) make the spin axis's role degenerate.
DEGENERATE_MOMENTS = 1e-9
# The maxima a cross-check file states (root attributes, SI units), by attribute name:
# (label, unit in the file, unit shown, factor from the file's unit to the shown one).
CROSSCHECK_MAXIMA = {
    "max_H_B_relative_difference": ("largest |H_B difference| / |H_B(t0)|", "1", "", 1.0),
    "max_attitude_difference": ("largest attitude difference", "rad", "deg",
                                180.0 / math.pi),
    "max_w_difference": ("largest hub angular-velocity difference", "rad/s", "deg/s",
                         180.0 / math.pi),
    "max_flip_time_difference": ("largest flip-time difference", "s", "s", 1.0),
}


def publish(tmp, out):
    """Renames the finished temporary file tmp onto out with the mode an ordinary file
    would get, 0666 less the umask (mkstemp creates it 0600)."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp, 0o666 & ~mask)
    os.replace(tmp, out)


class SceneError(Exception):
    """Bad input: the message is one line, naming the file and what is wrong."""


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


# --- rotations ----------------------------------------------------------------------------
def quat_to_matrix(q):
    """R (..., 3, 3) of unit quaternions q (..., 4), scalar first, Hamilton."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    R = np.empty(q.shape[:-1] + (3, 3))
    R[..., 0, 0] = 1 - 2 * (y * y + z * z)
    R[..., 0, 1] = 2 * (x * y - w * z)
    R[..., 0, 2] = 2 * (x * z + w * y)
    R[..., 1, 0] = 2 * (x * y + w * z)
    R[..., 1, 1] = 1 - 2 * (x * x + z * z)
    R[..., 1, 2] = 2 * (y * z - w * x)
    R[..., 2, 0] = 2 * (x * z - w * y)
    R[..., 2, 1] = 2 * (y * z + w * x)
    R[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def matrix_to_quat(R):
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R)
    if tr > 0:
        s = 2 * math.sqrt(1 + tr)
        q = [s / 4, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(max(1 + R[i, i] - R[j, j] - R[k, k], 1e-300))
        q = [0.0] * 4
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = s / 4
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


def axis_angle_matrix(a, theta):
    """Rot(a, theta): right-hand rotation by theta about the unit vector a (Rodrigues)."""
    a = np.asarray(a, dtype=float)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K


def quat_angle(q1, q2):
    """Rotation angle between unit quaternions (either sign), rad."""
    d = min(1.0, abs(float(np.dot(q1, q2))))
    return 2 * math.acos(d)


# --- geometry -----------------------------------------------------------------------------
def box_inertia(m, dims):
    a, b, c = dims
    return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def equivalent_box(m, I):
    """Edge lengths and axes (columns of V) of the uniform box of mass m with inertia I."""
    I = 0.5 * (np.asarray(I, dtype=float) + np.asarray(I, dtype=float).T)
    lam, V = np.linalg.eigh(I)
    if np.linalg.det(V) < 0:
        V[:, 2] = -V[:, 2]
    s = lam.sum()
    dims = np.sqrt(np.clip(6.0 / m * (s - 2 * lam), 0.0, None))  # d_i^2 = 6/m (I_j+I_k-I_i)
    return dims, V


def _vec(x, what, n=3):
    try:
        v = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"{what}: not a list of {n} numbers")
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise SceneError(f"{what}: not a list of {n} numbers")
    return v


def _element(d, what):
    """(mass, inertia about own CoM in own axes, dims, V) of a hub or panel entry."""
    m = float(d["mass"])
    if "box" in d:
        dims = _vec(d["box"], what + ".box")
        return m, box_inertia(m, dims), dims, np.eye(3)
    if "inertia" in d:
        I = np.asarray(d["inertia"], dtype=float)
        dims, V = equivalent_box(m, I)
        return m, I, dims, V
    raise SceneError(f"{what}: neither box nor inertia")


# How a part of the body is drawn, by the `drawn` shape of the trajectory's @body
# (docs/file_formats.md, "The body"): its kind in the pages (colour) and animation.
SHAPE_KINDS = {"box": "panel", "rod": "beam", "sphere": "bob", "none": "link"}


def _rod_axes(axis):
    """Columns: the unit axis, then two unit vectors across it (a right-handed frame)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    b = np.cross(a, helper)
    b /= np.linalg.norm(b)
    return np.column_stack([a, b, np.cross(a, b)])


def _drawn(m, I, drawn, what):
    """(dims, V, kind) of a @body element: its `drawn` shape (a rod along its axis, a
    sphere's bounding cube, nothing for a massless link) or its uniform box."""
    shape = drawn.get("shape", "box") if isinstance(drawn, dict) else "box"
    if shape not in SHAPE_KINDS:
        raise SceneError(f"{what}.drawn.shape = {shape!r}: not one of {sorted(SHAPE_KINDS)}")
    if shape == "rod":
        r = float(drawn["radius"])
        return (np.array([float(drawn["length"]), 2 * r, 2 * r]),
                _rod_axes(_vec(drawn["axis"], what + ".drawn.axis")), "beam")
    if shape == "sphere":
        return np.full(3, 2 * float(drawn["radius"])), np.eye(3), "bob"
    if shape == "none":
        return np.zeros(3), np.eye(3), "link"
    dims, V = equivalent_box(m, I)
    return dims, V, "panel"


class HingedModel:
    """A `kind: hinged` model (docs/file_formats.md) as drawable parts: from a trajectory's
    @body (the body as the run moved it, appendages expanded: HingedModel.from_body) or,
    for files written before it, from the model text's hub and panels."""

    def __init__(self, model):
        hub = model["hub"]
        self.hub_mass, self.hub_I, self.hub_dims, self.hub_V = _element(hub, "hub")
        self.hub_com = _vec(hub.get("com", [0, 0, 0]), "hub.com")
        panels = model["panels"]
        self.names = [str(p["name"]) for p in panels]
        self.panels = []
        for i, p in enumerate(panels):
            what = f"panels[{i}]"
            m, I, dims, V = _element(p, what)
            a = _vec(p["hinge_axis"], what + ".hinge_axis")
            self.panels.append(dict(
                name=str(p["name"]), mass=m, I=I, dims=dims, V=V, kind="panel",
                p=_vec(p["hinge_point"], what + ".hinge_point"), a=a / np.linalg.norm(a),
                r=_vec(p["com_offset"], what + ".com_offset"),
                parent=self.names.index(p["parent"]) if "parent" in p else -1))
        self.appendages = []
        self._finish()

    @classmethod
    def from_body(cls, body, path="@body"):
        """From a trajectory's @body (parsed JSON): every panel the run moved, each drawn
        as its `drawn` shape says; appendages as body["appendages"]."""
        self = cls.__new__(cls)
        try:
            hub = body["hub"]
            self.hub_mass = float(hub["mass"])
            self.hub_I = np.asarray(hub["inertia"], dtype=float)
            self.hub_com = _vec(hub["com"], path + ".hub.com")
            self.hub_dims, self.hub_V, _ = _drawn(self.hub_mass, self.hub_I, hub.get("drawn"),
                                                  path + ".hub")
            self.names = [str(p["name"]) for p in body["panels"]]
            self.panels = []
            for i, p in enumerate(body["panels"]):
                what = f"{path}.panels[{i}]"
                m, I = float(p["mass"]), np.asarray(p["inertia"], dtype=float)
                dims, V, kind = _drawn(m, I, p.get("drawn"), what)
                a = _vec(p["hinge_axis"], what + ".hinge_axis")
                parent = int(p["parent"])
                if not -1 <= parent < len(body["panels"]):
                    raise SceneError(f"{what}.parent = {parent}: no such panel")
                self.panels.append(dict(
                    name=str(p["name"]), mass=m, I=I, dims=dims, V=V, kind=kind,
                    p=_vec(p["hinge_point"], what + ".hinge_point"), a=a / np.linalg.norm(a),
                    r=_vec(p["com_offset"], what + ".com_offset"), parent=parent,
                    appendage=p.get("appendage")))
            self.appendages = list(body.get("appendages", []))
        except (KeyError, TypeError, ValueError) as e:
            raise SceneError(f"{path}: not a body record ({type(e).__name__}: {e})") from None
        self._finish()
        return self

    def _finish(self):
        """The drawing order (parents before children) and the parts' names and kinds."""
        self.order, placed = [], set()
        while len(self.order) < len(self.panels):
            before = len(self.order)
            for k, p in enumerate(self.panels):
                if k not in placed and (p["parent"] < 0 or p["parent"] in placed):
                    self.order.append(k)
                    placed.add(k)
            if len(self.order) == before:
                raise SceneError("panels: the parents form a cycle")
        self.part_names = ["hub"] + self.names
        self.part_kinds = ["hub"] + [p["kind"] for p in self.panels]

    def parts(self, angles):
        """Per part (hub first, then panels in model order): (mass, CoM in B, R_B part)."""
        P = len(self.panels)
        R = [None] * P
        o = [None] * P
        com = [None] * P
        for k in self.order:
            p = self.panels[k]
            if p["parent"] < 0:
                Rp, op = np.eye(3), np.zeros(3)
            else:
                Rp, op = R[p["parent"]], o[p["parent"]]
            R[k] = Rp @ axis_angle_matrix(p["a"], float(angles[k]))
            o[k] = op + Rp @ p["p"]
            com[k] = o[k] + R[k] @ p["r"]
        out = [(self.hub_mass, self.hub_com, np.eye(3))]
        out += [(self.panels[k]["mass"], com[k], R[k]) for k in range(P)]
        return out

    def inertia(self, angles):
        """(J about the system CoM in B, the system CoM c in B) at these hinge angles."""
        parts = self.parts(angles)
        M = sum(m for m, _, _ in parts)
        c = sum(m * x for m, x, _ in parts) / M
        I_own = [self.hub_I] + [p["I"] for p in self.panels]
        J = np.zeros((3, 3))
        for (m, x, R), I in zip(parts, I_own):
            d = x - c
            J += R @ I @ R.T + m * (d @ d * np.eye(3) - np.outer(d, d))
        return J, c

    def poses(self, angles):
        """Drawn boxes: list of (centre relative to the system CoM, R_B box, dims)."""
        parts = self.parts(angles)
        M = sum(m for m, _, _ in parts)
        c = sum(m * x for m, x, _ in parts) / M
        V = [self.hub_V] + [p["V"] for p in self.panels]
        dims = [self.hub_dims] + [p["dims"] for p in self.panels]
        return [(x - c, R @ v, d) for (m, x, R), v, d in zip(parts, V, dims)]


def tensor_poses(J, scale=None):
    """The uniform box with the principal moments of J (largest edge 1 unless scale)."""
    dims, V = equivalent_box(1.0, J)
    s = scale if scale is not None else (1.0 / dims.max() if dims.max() > 0 else 1.0)
    return [(np.zeros(3), V, dims * s)], s


def spin_axis(J0, H0):
    """docs/file_formats.md "Flips" 1: the principal axis of J0 nearest H0, along H0."""
    _, V = np.linalg.eigh(0.5 * (J0 + J0.T))
    h = H0 / np.linalg.norm(H0)
    c = V.T @ h
    i = int(np.argmax(np.abs(c)))
    return V[:, i] * (1.0 if c[i] >= 0 else -1.0)


# --- reading ------------------------------------------------------------------------------
def _need(f, name, path, what="deploysim trajectory"):
    if name not in f:
        raise SceneError(f"{path}: not a {what} (no dataset /{name})")
    return f[name][()]


def _attr(f, name):
    return _text(f.attrs[name]) if name in f.attrs else None


def _load_model(model_text, path):
    import yaml
    try:
        m = yaml.safe_load(model_text)
    except yaml.YAMLError as e:
        raise SceneError(f"{path}: model text is not YAML ({str(e).splitlines()[0]})")
    if not isinstance(m, dict) or m.get("kind") not in ("hinged", "tensors"):
        raise SceneError(f"{path}: model text has no kind hinged or tensors")
    return m


def _model_from_profile(profile_text, profile_source, path):
    """A cross-check file has no model text: the profile's `model:` key resolved against
    profile_source (as deploysim did)."""
    import yaml
    try:
        prof = yaml.safe_load(profile_text or "")
    except yaml.YAMLError:
        prof = None
    if not isinstance(prof, dict) or "model" not in prof:
        raise SceneError(f"{path}: profile_text names no model")
    mpath = os.path.join(os.path.dirname(profile_source or "."), str(prof["model"]))
    if not os.path.isfile(mpath):
        raise SceneError(f"{path}: the profile's model {mpath} is not readable "
                         "(a cross-check file holds no model text; pass --model)")
    with open(mpath) as fh:
        return prof, fh.read()


def _tensor_config(model, prof):
    """J of the configuration a tensor profile starts in (cross-check files only)."""
    confs = model.get("configurations") or {}
    name = None
    if isinstance(prof, dict):
        ini = prof.get("initial") or {}
        name = ini.get("configuration")
        st = prof.get("stages") or []
        if name is None and st:
            name = st[0].get("hold") or st[0].get("from")
    if name not in confs:
        name = next(iter(confs))
    c = confs[name]
    if "principal_moments" in c:
        return np.diag(np.asarray(c["principal_moments"], dtype=float))
    return np.asarray(c["tensor"], dtype=float)


def _schema(path):
    """The file's `schema` attribute (a cross-check file's), "" if none or unreadable (the
    trajectory reader then says what is wrong)."""
    import h5py
    try:
        with h5py.File(path, "r") as f:
            return _text(f.attrs.get("schema", ""))
    except OSError:
        return ""


def _read_crosscheck(path, model_path):
    """(run, time, sides, model text, profile) of a cross-check file (docs/file_formats.md,
    schema deploysim-crosscheck; not a trajectory file)."""
    import h5py
    what = "deploysim cross-check file"
    with h5py.File(path, "r") as f:
        run = dict(path=path, kind="crosscheck",
                   profile_name=_attr(f, "profile_name") or os.path.basename(path))
        t = _need(f, "time", path, what)
        sides = []
        for side, label in (("reduced", "reduced model"), ("simbody", "Simbody")):
            sides.append(dict(label=label, q=_need(f, side + "/q_NB", path, what),
                              H=_need(f, side + "/H_B", path, what),
                              h_N=_need(f, side + "/h_N", path, what),
                              w=f[side + "/w_NB_B"][()] if side + "/w_NB_B" in f else None,
                              flips=f[side + "/flip_time"][()] if side + "/flip_time" in f
                              else np.zeros(0)))
        run["hinge"] = f["simbody/hinge_angles"][()] if "simbody/hinge_angles" in f else None
        run["hinge_rates"] = (f["simbody/hinge_rates"][()] if "simbody/hinge_rates" in f
                              else None)
        prof, model_text = _model_from_profile(_attr(f, "profile_text"),
                                               _attr(f, "profile_source"), path) \
            if model_path is None else (None, open(model_path).read())
        run["J"] = None
        # No stage table, danger windows or hinge events in a cross-check file: the stages
        # and danger windows are derived from the motion (crosscheck_stages), once the
        # geometry is known.
        run["stages"], run["danger"], run["events"] = [], [], []
        run["outcome"] = None
        run["attrs"] = {k: float(f.attrs[k]) for k in CROSSCHECK_MAXIMA if k in f.attrs}
    return run, t, sides, model_text, prof


def _read_trajectory(path, model_path):
    """(run, time, sides, model text, None) of a trajectory file, read through
    tools/deploysim_results.py."""
    try:
        tr = results.read_trajectory(path)
        t = tr["time"]
        sides = [dict(label=tr.profile_name, q=tr["q_NB"], H=tr["H_B"], h_N=tr["h_N"],
                      w=tr.get("w_NB_B"), flips=tr.flip_time, angle=tr["spin_axis_angle"])]
        run = dict(path=path, kind="trajectory", profile_name=tr.profile_name,
                   J=tr["J_B"], hinge=tr.get("hinge_angles"),
                   hinge_rates=tr.get("hinge_rates"), attrs={})
        model_text = open(model_path).read() if model_path is not None \
            else tr.attr("model_text")
        run["body"] = tr.body
        run["stages"] = [dict(name=s["name"], t0=float(s["t_begin"]), t1=float(s["t_end"]),
                              role=s["spin_axis_role"]) for s in tr.stages]
        run["danger"] = [[a, b] for a, b in tr.danger_windows]
        # The run's outcome record (the verdict analyze and the report print), if any.
        o = tr.outcome
        run["outcome"] = None if o is None else dict(
            headline=o["headline"], name=o["name"], cls=o["class"],
            phase_begin=o["phase_begin"], transition_time=o["transition_time"])
        # Every row of the hinge event table (stop impacts too: the viewer groups their
        # bursts; the 3D markers and banners leave them out). Angles and rates in SI.
        run["events"] = [dict(t=float(e["time"]), kind=e["kind"], panel=e["panel_name"],
                              angle=float(e["angle"]), rate_before=float(e["rate_before"]),
                              rate_after=float(e["rate_after"]),
                              impulse=float(e["impulse"]))
                         for e in tr.hinge_events]
    except results.TrajectoryError as e:
        raise SceneError(str(e)) from None
    return run, t, sides, model_text, None


def read_run(path, model_path=None):
    """Reads a trajectory or cross-check file into a dict of numpy arrays (SceneError on
    anything that is not one)."""
    if _schema(path).startswith("deploysim-crosscheck"):
        run, t, sides, model_text, prof = _read_crosscheck(path, model_path)
    else:
        run, t, sides, model_text, prof = _read_trajectory(path, model_path)
    t = np.asarray(t, dtype=float)
    n = len(t)
    if n < 2:
        raise SceneError(f"{path}: fewer than two samples")
    for s in sides:
        if s["q"].shape != (n, 4) or s["H"].shape != (n, 3):
            raise SceneError(f"{path}: /q_NB or /H_B does not match /time ({n} samples)")
        if not (np.all(np.isfinite(s["q"])) and np.all(np.isfinite(s["H"]))):
            raise SceneError(f"{path}: /q_NB or /H_B holds non-finite values")
    model = _load_model(model_text, path)
    run["time"], run["sides"], run["model_name"] = t, sides, str(model.get("name", "?"))
    hinge = run["hinge"]
    # The body as the run moved it where the file has it (appendages expanded by deploysim
    # itself); else, or with --model, the model text's hub and panels.
    body = run.pop("body", None) if model_path is None else None
    if model["kind"] == "hinged" and hinge is not None:
        run["geometry"] = (HingedModel.from_body(body, f"{path}: @body") if body is not None
                           else HingedModel(model))
        if hinge.shape != (n, len(run["geometry"].panels)):
            raise SceneError(f"{path}: /hinge_angles has {hinge.shape[1]} columns, the model "
                             f"{len(run['geometry'].panels)} panels")
        if run["J"] is None:  # cross-check: J from the geometry at the first angles
            J0, _ = run["geometry"].inertia(hinge[0])
        else:
            J0 = run["J"][0]
    else:
        run["geometry"] = None
        if run["J"] is None:
            if model["kind"] == "hinged":
                raise SceneError(f"{path}: a hinged model without hinge angles")
            run["J"] = np.repeat(_tensor_config(model, prof)[None], n, axis=0)
        J0 = run["J"][0]
    s_B = spin_axis(J0, sides[0]["H"][0])
    run["spin_axis_B"] = s_B
    for s in sides:
        if "angle" not in s:
            Hn = s["H"] / np.linalg.norm(s["H"], axis=1)[:, None]
            s["angle"] = np.arccos(np.clip(Hn @ s_B, -1, 1))
    if run["kind"] == "crosscheck":
        run["stages"], run["danger"] = crosscheck_stages(run)
    if run["geometry"] is not None and run["geometry"].appendages:
        _group_appendages(run)
    return run


# --- appendages ---------------------------------------------------------------------------
def bending_owners(appendages):
    """{panel index: appendage name} of the appendages' generated bending hinges (@body's
    appendages[].hinges; a beam's root stub is an ordinary panel)."""
    return {int(h): a["name"] for a in appendages for h in a["hinges"]}


def hinge_channels(names, appendages):
    """The lines of a hinge chart: (names, hinge columns summed per line). Every panel's
    own hinge, except an appendage's bending hinges: per beam and bending plane one line,
    the sum of the plane's hinge angles (the tip's slope relative to the root: the beam's
    bend), named "<beam> bend" ("bend 1", "bend 2" for two planes); a slosh pendulum's
    hinges each a line of their own. Used by the viewer and tools/plot_trajectory.py."""
    owner = bending_owners(appendages)
    out_names = [n for k, n in enumerate(names) if k not in owner]
    columns = [[k] for k in range(len(names)) if k not in owner]
    for a in appendages:
        if a["kind"] != "beam":
            out_names += [names[k] for k in a["hinges"]]
            columns += [[k] for k in a["hinges"]]
            continue
        planes = max(1, int(a["planes"]))
        for p in range(planes):
            out_names.append(f"{a['name']} bend" + (f" {p + 1}" if planes > 1 else ""))
            columns.append(list(a["hinges"][p::planes]))
    return out_names, columns


def phase_label(name, panel_names, appendages):
    """A hinge profile's phase name as the pages show it, as the CLI's text does
    (cli/report.cc PhaseLabel): each list of panels ("free: a, b; moved: c") with an
    appendage's bending hinges named once, by the appendage and their count:
    "free: boom_px (12), boom_mx (6)"."""
    owner = {panel_names[k]: a for k, a in bending_owners(appendages).items()}
    if not owner:
        return name
    parts = []
    for part in name.split("; "):
        head, sep, items = part.partition(": ")
        if not sep:
            parts.append(part)
            continue
        shown, count = [], {}
        for item in items.split(", "):
            a = owner.get(item)
            if a is None:
                shown.append(item)
            else:
                if a not in count:
                    count[a] = 0
                    shown.append(a)  # its slot, filled below
                count[a] += 1
        parts.append(head + sep + ", ".join(f"{x} ({count[x]})" if x in count else x
                                            for x in shown))
    return "; ".join(parts)


def _group_appendages(run):
    """The pages' view of a body with appendages: the phase names grouped (phase_label),
    and the releases of the bending hinges at the run's start (free from the start by
    construction) as one event per appendage, as the CLI's timeline states them once."""
    g = run["geometry"]
    for st in run["stages"]:
        st["name"] = phase_label(st["name"], g.names, g.appendages)
    owner = {g.names[k]: a for k, a in bending_owners(g.appendages).items()}
    t0 = float(run["time"][0])
    events, grouped = [], {}
    for e in run["events"]:
        a = owner.get(e["panel"])
        if a is None or e["kind"] != "release" or e["t"] > t0:
            events.append(e)
            continue
        if a not in grouped:
            grouped[a] = dict(e, panel=a, count=0)
            events.append(grouped[a])
        grouped[a]["count"] += 1
    for e in grouped.values():
        e["text"] = f"{e['panel']}: its {e['count']} hinges free from the start"
    run["events"] = events


def trail_seconds(run):
    """How much of the spin axis's path to draw [s]: TRAIL_SECONDS, or two median flip
    intervals (the first side's flips) where that is shorter."""
    f = np.asarray(run["sides"][0]["flips"], dtype=float)
    if len(f) >= 2:
        return float(min(TRAIL_SECONDS, 2.0 * np.median(np.diff(f))))
    return TRAIL_SECONDS


# --- derived tables (cross-check files) ---------------------------------------------------
def axis_role(J, s_B):
    """The role of the principal axis of J nearest s_B (analysis::LocateSpinAxis: minor,
    intermediate, major, or degenerate within DEGENERATE_MOMENTS of the largest moment)."""
    lam, V = np.linalg.eigh(0.5 * (J + J.T))
    i = int(np.argmax(np.abs(V.T @ s_B)))
    low = lam[1] - lam[0] <= DEGENERATE_MOMENTS * lam[2]
    high = lam[2] - lam[1] <= DEGENERATE_MOMENTS * lam[2]
    if (i == 1 and (low or high)) or (i == 0 and low) or (i == 2 and high):
        return "degenerate"
    return ("minor", "intermediate", "major")[i]


def moving_span(run):
    """(first, last) time at which a hinge angle changes (more than HINGE_MOTION rad
    between samples), or None: no hinges, or none moves. An appendage's bending hinges
    do not count."""
    h = run["hinge"]
    if h is None or len(h) < 2:
        return None
    g = run.get("geometry")
    if g is not None and g.appendages:  # bending hinges flex all the time: not a deployment
        owner = bending_owners(g.appendages)
        h = h[:, [k for k in range(h.shape[1]) if k not in owner]]
        if h.shape[1] == 0:
            return None
    moving = np.nonzero(np.abs(np.diff(h, axis=0)).max(axis=1) > HINGE_MOTION)[0]
    if len(moving) == 0:
        return None
    t = run["time"]
    return float(t[moving[0]]), float(t[moving[-1] + 1])


def crosscheck_stages(run):
    """Stages and danger windows of a cross-check run, derived from its motion (the file
    has neither table): the span before, during and after the hinges move (Simbody's hinge
    angles), each named for its spin-axis role at its end as in a trajectory's stage
    table; danger windows where the spin axis is the intermediate principal axis of J_B(t)
    (as /danger_windows: first and last sample)."""
    t = run["time"]
    n = len(t)
    s_B = run["spin_axis_B"]
    if run["geometry"] is not None:
        step = max(1, n // 2000)
        idx = np.unique(np.r_[np.arange(0, n, step), n - 1])
        roles = [axis_role(run["geometry"].inertia(run["hinge"][i])[0], s_B) for i in idx]
    else:
        idx = np.array([0, n - 1])
        roles = [axis_role(run["J"][i], s_B) for i in idx]
    tt = t[idx]
    span = moving_span(run)
    if span is None:
        cuts = [(float(t[0]), float(t[-1]), "whole run")]
    else:
        cuts = [(float(t[0]), span[0], "stowed"), (span[0], span[1], "deploying"),
                (span[1], float(t[-1]), "deployed")]

    def role_at(x):
        return roles[min(int(np.searchsorted(tt, x, side="right")) - 1, len(roles) - 1)]

    stages = [dict(name=name, t0=a, t1=b, role=role_at(b), derived=True)
              for a, b, name in cuts if b > a]
    danger, start = [], None
    for x, r in zip(tt, roles):
        if r == "intermediate" and start is None:
            start = float(x)
        if r != "intermediate" and start is not None:
            danger.append([start, last])
            start = None
        last = float(x)
    if start is not None:
        danger.append([start, float(tt[-1])])
    return stages, danger


# --- what to draw -------------------------------------------------------------------------
def decimate(run):
    """Indices of the samples to keep (first and last always): each kept sample is the
    last one within the steps of the kept one before it."""
    t = run["time"]
    n = len(t)
    qs = [s["q"] / np.linalg.norm(s["q"], axis=1)[:, None] for s in run["sides"]]
    hinge, J = run["hinge"], run["J"]
    Jscale = np.abs(J).max() if J is not None else 1.0
    gap = MAX_GAP * (t[-1] - t[0])

    def beyond(i, last):
        return (max(quat_angle(q[i], q[last]) for q in qs) > ROTATION_STEP
                or (hinge is not None and np.abs(hinge[i] - hinge[last]).max() > HINGE_STEP)
                or (J is not None and np.abs(J[i] - J[last]).max() > J_STEP * Jscale)
                or t[i] - t[last] > gap)

    keep, last, i = [0], 0, 1
    while i < n - 1:
        if beyond(i, last):
            last = i - 1 if i - 1 > last else i
            keep.append(last)
        i = max(i + 1, last + 1)
    keep.append(n - 1)
    return np.array(sorted(set(keep)))


def interpolation_error(run, idx):
    """Largest angle [rad] between a sample's attitude and the slerp of the kept samples
    around it (what the viewer draws), over all sides."""
    t, worst = run["time"], 0.0
    for s in run["sides"]:
        q = s["q"] / np.linalg.norm(s["q"], axis=1)[:, None]
        for a, b in zip(idx[:-1], idx[1:]):
            if b - a < 2:
                continue
            q0, q1 = q[a], q[b] if q[a] @ q[b] >= 0 else -q[b]
            om = math.acos(min(1.0, float(q0 @ q1)))
            f = (t[a + 1:b] - t[a]) / (t[b] - t[a])
            if om < 1e-12:
                qi = np.repeat(q0[None], len(f), axis=0)
            else:
                qi = (np.sin((1 - f) * om)[:, None] * q0 + np.sin(f * om)[:, None] * q1) / math.sin(om)
            d = np.clip(np.abs(np.sum(qi / np.linalg.norm(qi, axis=1)[:, None] * q[a + 1:b],
                                      axis=1)), 0, 1)
            worst = max(worst, float(2 * np.arccos(d).max()))
    return worst


def poses_at(run, i, scale=None):
    """Boxes at sample i: list of (centre in B rel. the system CoM, R_B box, dims)."""
    if run["geometry"] is not None:
        return run["geometry"].poses(run["hinge"][i])
    p, _ = tensor_poses(run["J"][i], scale)
    return p


def tensor_scale(run):
    """One scale for the equivalent box over the whole run (largest edge ever = 1)."""
    if run["geometry"] is not None:
        return None
    m = max(equivalent_box(1.0, run["J"][i])[0].max() for i in (0, len(run["time"]) - 1))
    return 1.0 / m if m > 0 else 1.0


def part_names(run):
    if run["geometry"] is not None:
        return run["geometry"].part_names, run["geometry"].part_kinds
    return ["equivalent box"], ["hub"]


def extent(run, idx, scale):
    """Largest distance of a box corner from the system CoM over the kept samples."""
    corners = np.array([[sx, sy, sz] for sx in (-.5, .5) for sy in (-.5, .5) for sz in (-.5, .5)])
    r = 0.0
    step = max(1, len(idx) // 50)
    for i in list(idx[::step]) + [idx[-1]]:
        for c, R, d in poses_at(run, i, scale):
            r = max(r, np.linalg.norm(c + (corners * d) @ R.T, axis=1).max())
    return r
