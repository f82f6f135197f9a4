"""FreeBody: the closed form over numpy arrays equals the scalar C++ path, and the
reference numbers of docs/design.md section 6."""

import numpy as np
import pytest

import deploysim

WING_NUT_J = [3.036e-6, 2.741e-6, 0.699e-6]
WING_NUT_H0 = [1e-8, 2.1252e-5, 1e-8]


@pytest.fixture
def wing_nut():
    return deploysim.FreeBody(WING_NUT_J, WING_NUT_H0)


def test_reference_numbers(wing_nut):
    assert wing_nut.regime == "minor-axis"
    assert wing_nut.one_minus_k2 == pytest.approx(6.6492854004460934e-6, rel=1e-12)
    assert wing_nut.lambda_ == pytest.approx(4.1308713587499453, rel=1e-13)
    assert wing_nut.period == pytest.approx(7.1140491749608600, rel=1e-13)
    assert wing_nut.flip_half_period == pytest.approx(3.5570245874804300, rel=1e-13)
    flips = wing_nut.flip_times(0.0, 40.0)
    assert len(flips) == 11
    assert flips[:4] == pytest.approx([1.7338627960581041, 5.2908873835385341,
                                       8.8479119710189641, 12.404936558499394], abs=1e-12)
    assert wing_nut.intermediate_axis == 1


@pytest.mark.parametrize("method", ["H_B", "w_NB_B", "q_NB"])
def test_vectorized_equals_scalar_bit_for_bit(wing_nut, method):
    t = np.linspace(-5.0, 40.0, 1001)
    f = getattr(wing_nut, method)
    vec = f(t)
    assert vec.shape == (1001, 4 if method == "q_NB" else 3)
    for k in range(0, 1001, 7):
        assert np.array_equal(vec[k], f(float(t[k])))
    # Any shape of times: the result has one more axis.
    assert f(t.reshape(7, 11, 13)).shape == (7, 11, 13, vec.shape[1])
    assert np.array_equal(f(t.reshape(7, 11, 13)).reshape(-1, vec.shape[1]), vec)
    assert f(3.0).shape == (vec.shape[1],)
    assert np.array_equal(f([1.0, 2.0]), f(np.array([1.0, 2.0])))


def test_state_equals_the_separate_calls(wing_nut):
    t = np.linspace(0.0, 40.0, 401)
    H, q = wing_nut.state(t)
    assert np.array_equal(H, wing_nut.H_B(t))
    assert np.array_equal(q, wing_nut.q_NB(t))


def test_invariants(wing_nut):
    t = np.linspace(0.0, 40.0, 4001)
    H = wing_nut.H_B(t)
    M = np.linalg.norm(WING_NUT_H0)
    assert np.max(np.abs(np.linalg.norm(H, axis=1) - M)) < 1e-15 * M * 10
    q = wing_nut.q_NB(t)
    w, v = q[:, :1], q[:, 1:]
    # h_N = R_NB H_B (Hamilton, scalar first): constant.
    Hv = H
    t2 = 2.0 * np.cross(v, Hv)
    h_N = Hv + w * t2 + np.cross(v, t2)
    assert np.max(np.abs(h_N - h_N[0])) < 1e-13 * M


def test_full_tensor_and_errors():
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    J = R @ np.diag(WING_NUT_J) @ R.T
    fb = deploysim.FreeBody(J, R @ np.array(WING_NUT_H0))
    assert fb.period == pytest.approx(7.1140491749608600, rel=1e-9)
    with pytest.raises(ValueError):
        deploysim.FreeBody([1.0, 1.0, 3.0], [0.0, 0.0, 1.0])  # triangle inequality
    with pytest.raises(ValueError):
        deploysim.FreeBody(WING_NUT_J, [0.0, float("nan"), 1.0])
    with pytest.raises(ValueError):
        deploysim.FreeBody(WING_NUT_J, [0.0, 1.0])
