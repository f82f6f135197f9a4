#!/usr/bin/python3
"""Reads a deploysim trajectory file (HDF5 written by `deploysim simulate`; layout in
docs/file_formats.md, "Trajectory files") for the tools: one reader, one error type, and
the one place that knows how older files differ.

    from deploysim_results import read_trajectory, TrajectoryError
    run = read_trajectory("run.h5")
    run["H_B"]                 # any dataset by its path, numpy array (text: list of str)
    run.samples                # every per-sample dataset at the root, by name
    run.attrs["integrator"]    # the root attributes, as str
    run.attr_fields("statistics")["steps"]      # "steps=..., rejected=..." as a dict
    run.body, run.appendages    # the hinged body as the run moved it (@body), or None
    run.stages, run.hinge_events                # the tables, one dict per row
    run.danger_windows, run.latch_times, run.panel_names

Files of schema version 2 only (the root attribute `schema_version`). Version 2 files
written before the free-hinge outputs (docs/file_formats.md, "Additions for free hinges")
lack some datasets; the reader fills them in as such a run would have written them (no
springs, no hinge events, no 45-degree crossings, no caveats: _fallbacks), lists them in
`run.filled` and sets `run.has_hinge_outputs` false (as io::ReadTrajectoryFile does, by
the presence of /energy_spring: the additions come all or none). Every other dataset is
read as the file has it; asking for one the file does not have raises TrajectoryError
naming the file and the dataset. Text is decoded to str here, once.

Needs Debian's python3-h5py and python3-numpy (run with /usr/bin/python3).
"""
import json
import os

import numpy as np

SCHEMA_VERSION = "2"

# Root datasets with one row per panel (not per sample), whatever their length.
PER_PANEL = ("panel_names", "hinge_latch_time")

# The columns of the hinge event table /events/hinge/* (for its empty stand-in).
HINGE_EVENT_TEXT = ("panel_name", "kind")
HINGE_EVENT_NUMBERS = ("time", "angle", "rate_before", "rate_after", "impulse",
                       "energy_dissipated", "drive_work")


class TrajectoryError(Exception):
    """A trajectory file that cannot be read: one line naming the file and what is wrong
    (the dataset or attribute missing, the version)."""


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def _value(raw):
    """A dataset's content: text as a list of str, numbers as a numpy array (a scalar
    dataset as a Python number)."""
    if isinstance(raw, np.ndarray) and raw.dtype.kind in "OSU":
        return [_text(x) for x in raw.tolist()]
    if isinstance(raw, (bytes, str)):
        return _text(raw)
    if isinstance(raw, np.generic):
        return raw.item()
    return raw


def _item(v):
    return v.item() if isinstance(v, np.generic) else v


def _fallbacks(data):
    """The stand-ins for the datasets added to version 2 with the free hinges, for files
    written before them: {path: value}. /hinge_rates has none (an older run's prescribed
    hinge rates are not in its file: run.get("hinge_rates") is None); /panel_names are
    "panel 0", "panel 1", ... in geometry mode, none in tensor mode."""
    n = len(data["time"])
    energy_spring = np.zeros(n)
    angles = data.get("hinge_angles")
    stages = len(data["stages/t_begin"]) if "stages/t_begin" in data else 0
    out = {
        "energy_spring": energy_spring,
        "hinge_latch_time": np.zeros(0),
        "events/spin_axis_45_time": np.zeros(0),
        "events/hinge/panel": np.zeros(0, dtype=np.int64),
        "events/hinge/w_jump_B": np.zeros((0, 3)),
        "stages/caveat": [""] * stages,
        "stages/rigid_body_only": np.zeros(stages, dtype=np.int64),
    }
    out.update({"events/hinge/" + k: [] for k in HINGE_EVENT_TEXT})
    out.update({"events/hinge/" + k: np.zeros(0) for k in HINGE_EVENT_NUMBERS})
    # Added later: a file with hinge events but no drive work recorded reads 0 for each.
    out["events/hinge/drive_work"] = np.zeros(len(data.get("events/hinge/time", [])))
    if "energy" in data:
        out["energy_total"] = data["energy"] + data.get("energy_spring", energy_spring)
    if angles is not None:
        out["panel_names"] = [f"panel {k}" for k in range(angles.shape[1])]
    return out


def _open(path):
    """The h5py File, after the checks that give the clear errors."""
    import h5py
    if not os.path.exists(path):
        raise TrajectoryError(f"{path}: no such file")
    if not os.path.isfile(path):
        raise TrajectoryError(f"{path}: not a file")
    try:
        if not h5py.is_hdf5(path):
            raise TrajectoryError(f"{path}: not an HDF5 file")
        return h5py.File(path, "r")
    except OSError as e:
        raise TrajectoryError(f"{path}: cannot read ({str(e).splitlines()[0]})") from None


def is_hdf5(path):
    """True if path is an HDF5 file of any kind (for tools that take a trajectory or
    something else)."""
    import h5py
    return os.path.isfile(path) and h5py.is_hdf5(path)


def read_trajectory(path):
    """The trajectory file at path as a Trajectory (TrajectoryError on anything else)."""
    import h5py
    with _open(path) as f:
        attrs = {k: _text(v) for k, v in f.attrs.items()}
        if "schema_version" not in attrs:
            raise TrajectoryError(f"{path}: not a deploysim trajectory (no schema_version "
                                  "attribute)")
        if attrs["schema_version"] != SCHEMA_VERSION:
            raise TrajectoryError(f"{path}: schema_version {attrs['schema_version']}: this "
                                  f"reader reads version {SCHEMA_VERSION} only")
        if not isinstance(f.get("time"), h5py.Dataset):
            raise TrajectoryError(f"{path}: not a deploysim trajectory (no dataset /time)")
        data = {}

        def read(name, obj):
            if isinstance(obj, h5py.Dataset):
                data[name] = _value(obj[()])
        f.visititems(read)
    filled = []
    for name, value in _fallbacks(data).items():
        if name not in data:
            data[name] = value
            filled.append(name)
    return Trajectory(path, attrs, data, filled)


class Trajectory:
    """One trajectory file's contents (read_trajectory). Datasets by path, without or
    with the leading slash: run["stages/t_end"], run["/H_B"]."""

    def __init__(self, path, attrs, data, filled):
        self.path = path
        self.attrs = attrs
        self.filled = filled
        self._data = data
        self.has_hinge_outputs = "energy_spring" not in filled
        n = len(data["time"])
        self.samples = {k: v for k, v in data.items()
                        if "/" not in k and k not in PER_PANEL and isinstance(v, np.ndarray)
                        and v.ndim >= 1 and v.shape[0] == n}

    # --- datasets and attributes -------------------------------------------------------
    def __getitem__(self, name):
        name = name.lstrip("/")
        if name not in self._data:
            raise self._missing(name)
        return self._data[name]

    def _missing(self, name):
        return TrajectoryError(f"{self.path}: not a deploysim trajectory (no dataset /{name})")

    def __contains__(self, name):
        return name.lstrip("/") in self._data

    def get(self, name, default=None):
        """The dataset at name, or default if the file has none (hinge angles and rates:
        geometry mode only)."""
        return self._data.get(name.lstrip("/"), default)

    def attr(self, name):
        """A root attribute (str); TrajectoryError naming it if the file has none."""
        if name not in self.attrs:
            raise TrajectoryError(f"{self.path}: not a deploysim trajectory (no attribute "
                                  f"@{name})")
        return self.attrs[name]

    def attr_fields(self, name):
        """A root attribute of the form "k=v, k=v" (statistics, integrator_settings) as a
        dict of str."""
        out = {}
        for part in self.attr(name).split(","):
            if "=" in part:
                k, v = part.split("=", 1)
                out[k.strip()] = v.strip()
        return out

    @property
    def outcome(self):
        """The run's outcome record (the @outcome attribute, JSON: the "outcome" of
        `deploysim analyze --json`), or None for a file written before it."""
        text = self.attrs.get("outcome")
        return json.loads(text) if text else None

    @property
    def warnings(self):
        """The profile's warnings (the @warnings attribute, a JSON array of one-line
        strings: docs/file_formats.md, "Warnings"); [] for a file written before it."""
        text = self.attrs.get("warnings")
        return json.loads(text) if text else []

    @property
    def body(self):
        """A hinged model's body as the run moved it (the @body attribute, JSON:
        docs/file_formats.md, "The body": hub, panels with the appendages' generated ones,
        appendages), or None (a tensors model, or a file written before it: the body is
        then the model text's)."""
        text = self.attrs.get("body")
        return json.loads(text) if text else None

    @property
    def appendages(self):
        """body["appendages"]: one dict per flexible appendage ([] without a body)."""
        b = self.body
        return b["appendages"] if b else []

    @property
    def time(self):
        return self["time"]

    @property
    def profile_name(self):
        return self.attrs.get("profile_name") or os.path.basename(self.path)

    # --- events and tables -------------------------------------------------------------
    @property
    def flip_time(self):
        return self["events/flip_time"]

    @property
    def predicted_flip_time(self):
        return self["events/predicted_flip_time"]

    @property
    def spin_axis_45_time(self):
        return self["events/spin_axis_45_time"]

    def _rows(self, group):
        """The table group/* as one dict per row (its length: the column time or t_begin)."""
        cols = {k[len(group) + 1:]: v for k, v in self._data.items()
                if k.startswith(group + "/") and "/" not in k[len(group) + 1:]}
        n = len(self[group + "/time" if group == "events/hinge" else group + "/t_begin"])
        return [{k: _item(v[i]) for k, v in cols.items()} for i in range(n)]

    @property
    def stage_columns(self):
        """The stage table /stages/* as {column: array or list of str} (TrajectoryError if
        the file has none)."""
        if "stages/t_begin" not in self:
            raise self._missing("stages/t_begin")
        return {k[len("stages/"):]: v for k, v in self._data.items()
                if k.startswith("stages/")}

    @property
    def stages(self):
        """The stage table, one dict per row (keys: the columns of /stages/*), each with
        the rows of its located flips in /events/flip_time (t_begin <= t < t_end) as
        "flip_rows" and of its predicted flips in /events/predicted_flip_time (stored in
        stage order, /stages/predicted_flip_count each) as "predicted_flip_rows"."""
        rows = self._rows("stages")
        flips = self.flip_time
        first = 0
        for s in rows:
            s["flip_rows"] = [k for k, t in enumerate(flips) if s["t_begin"] <= t < s["t_end"]]
            count = s["predicted_flip_count"]
            s["predicted_flip_rows"] = list(range(first, first + count))
            first += count
        return rows

    @property
    def hinge_events(self):
        """The hinge event table /events/hinge/*, one dict per event (keys: its columns)."""
        return self._rows("events/hinge")

    @property
    def danger_windows(self):
        """[(t_begin, t_end)] of /danger_windows/*."""
        return [(float(a), float(b)) for a, b in zip(self["danger_windows/t_begin"],
                                                     self["danger_windows/t_end"])]

    @property
    def panel_names(self):
        """The panels' names in the order of the columns of /hinge_angles (none in tensor
        mode)."""
        return self.get("panel_names", [])

    @property
    def latch_times(self):
        """{panel name: time it locked, NaN if never}; empty for stage profiles."""
        lt = self["hinge_latch_time"]
        return dict(zip(self.panel_names, (float(t) for t in lt))) if len(lt) else {}
