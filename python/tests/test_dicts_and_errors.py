"""Profiles and models from files and from dicts: the same rules, the same one-line
messages as the CLI (the corpus tests/io/bad_inputs), the same runs bit for bit."""

import math
import re

import numpy as np
import pytest

import deploysim
import yaml12
from conftest import PROFILES, SOURCE_DIR

CORPUS = sorted((SOURCE_DIR / "tests/io/bad_inputs").glob("*.yaml"))
BAD = [p for p in CORPUS if p.read_text(errors="replace").startswith("# expect: ")]


def expected(path):
    return path.read_text(errors="replace").split("\n", 1)[0][len("# expect: "):]


def is_profile(path):
    # The rule of tests/io/bad_inputs_test.cpp.
    return re.search(r"(^|\n)(stages|model|base)[ \t]*:", path.read_text(errors="replace")) is not None


def load_error(path):
    try:
        if is_profile(path):
            deploysim.load_profile(path)
        else:
            deploysim.load_model(path)
    except (ValueError, RuntimeError) as e:
        return type(e), str(e)
    return None, ""


def test_corpus_is_there():
    assert len(BAD) >= 30


@pytest.mark.parametrize("path", BAD, ids=[p.stem for p in BAD])
def test_bad_file_message_is_the_clis(path, cli, tmp_path):
    kind, message = load_error(path)
    assert kind is not None, f"{path} was accepted"
    assert expected(path) in message
    assert message.startswith(str(path) + ": ")
    assert "\n" not in message
    if is_profile(path):
        r = cli("analyze", path, check=False)
        assert r.returncode == 1
        assert r.stderr == f"deploysim: error: {message}\n"


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?\.(?:inf|nan|Inf|NaN)")


def normalized(message):
    """Numbers as their values (a dict's 0.001 is a file's 1e-3), and strings without
    their quotes (a file may quote a string that a dict writes plain)."""
    message = message.replace('"', "")
    # Positions in the text: a dict's text is written by the package, not the user.
    message = re.sub(r"line \d+, (column|byte offset) \d+: ", "", message)
    def value(m):
        t = m.group(0).replace(".inf", "inf").replace(".Inf", "inf").replace(".nan", "nan")
        t = t.replace(".NaN", "nan")
        try:
            return repr(float(t))
        except ValueError:
            return t
    return NUMBER.sub(value, message)


def as_dict(path):
    """The file as the dict a user would write, or None if it is not one (YAML syntax,
    aliases, tags, several documents, text that is no mapping)."""
    text = path.read_text(errors="replace")
    if re.search(r"[&*!]", text.split("\n", 1)[1]):
        return None
    try:
        d = yaml12.load(path)
    except Exception:  # noqa: BLE001 - not expressible as a dict
        return None
    return d if isinstance(d, dict) else None


# Files whose fault a dict cannot carry (the YAML text itself is the fault).
TEXT_ONLY = {
    "model_duplicate_configuration": "a dict has no duplicate keys",
    "profile_duplicate_top_key": "a dict has no duplicate keys",
}


@pytest.mark.parametrize("path", BAD, ids=[p.stem for p in BAD])
def test_bad_dict_message_is_the_files(path):
    d = as_dict(path)
    if path.stem in TEXT_ONLY:
        pytest.skip(TEXT_ONLY[path.stem])
    if d is None:
        pytest.skip("not expressible as a dict (YAML syntax, aliases, tags or no mapping)")
    kind, message = load_error(path)
    try:
        if is_profile(path):
            deploysim.profile_from_dict(d, source=str(path), base_dir=path.parent)
        else:
            deploysim.model_from_dict(d, source=str(path))
    except (ValueError, RuntimeError) as e:
        assert type(e) is kind
        assert normalized(str(e)) == normalized(message)
        return
    pytest.fail(f"the dict of {path.name} was accepted; the file: {message}")


@pytest.mark.parametrize("path", PROFILES, ids=[p.stem for p in PROFILES])
def test_dict_profile_runs_like_the_file(path):
    from_file = deploysim.load_profile(path)
    d = yaml12.load(path)
    from_dict = deploysim.profile_from_dict(d, source="dict", base_dir=path.parent)
    for k in ("name", "description", "mode", "coupling", "t_begin", "t_end", "method", "rtol",
              "atol", "step", "dt", "stages", "is_hinge_profile"):
        assert getattr(from_dict, k) == getattr(from_file, k), k
    assert from_dict.model.text == from_file.model.text
    a = deploysim.simulate(from_file, dt=max(from_file.dt, from_file.t_end / 200))
    b = deploysim.simulate(from_dict, dt=max(from_file.dt, from_file.t_end / 200))
    for k in (c["name"] for c in deploysim.trajectory_columns()):
        assert np.array_equal(getattr(a, k), getattr(b, k), equal_nan=True), k
    assert np.array_equal(a.flips, b.flips)


def test_model_dict_inside_a_profile_dict():
    path = SOURCE_DIR / "deployment_profiles/wing_nut.yaml"
    d = yaml12.load(path)
    model_path = (path.parent / d["model"]).resolve()
    d["model"] = yaml12.load(model_path)
    p = deploysim.profile_from_dict(d)
    q = deploysim.load_profile(path)
    assert p.model.name == q.model.name
    a, b = deploysim.simulate(p), deploysim.simulate(q)
    assert np.array_equal(a.H_B, b.H_B) and np.array_equal(a.q_NB, b.q_NB)
    # A Model object works too.
    d["model"] = deploysim.load_model(model_path)
    assert np.array_equal(deploysim.simulate(deploysim.profile_from_dict(d)).H_B, a.H_B)


def test_dict_errors_name_key_value_and_rule():
    d = yaml12.load(SOURCE_DIR / "deployment_profiles/wing_nut.yaml")
    d["integrator"]["rtol"] = -1.0
    with pytest.raises(ValueError) as e:
        deploysim.profile_from_dict(d, base_dir=SOURCE_DIR / "deployment_profiles")
    assert str(e.value) == "<dict>: integrator.rtol = -1: must be in [1e-14, 0.001]"
    d["integrator"]["rtol"] = 1e-10
    d["typo"] = 1
    with pytest.raises(ValueError, match=r"^<dict>: typo = 1: unknown key"):
        deploysim.profile_from_dict(d, base_dir=SOURCE_DIR / "deployment_profiles")
    del d["typo"]
    d["initial"]["angular_momentum"] = [1.0, math.nan, 0.0]
    with pytest.raises(ValueError, match=r"initial.angular_momentum"):
        deploysim.profile_from_dict(d, base_dir=SOURCE_DIR / "deployment_profiles")
    d["initial"]["angular_momentum"] = np.array([1e-8, 2.1252e-5, 1e-8])  # numpy is fine
    deploysim.profile_from_dict(d, base_dir=SOURCE_DIR / "deployment_profiles")
    with pytest.raises(TypeError):
        deploysim.profile_from_dict([1, 2])
