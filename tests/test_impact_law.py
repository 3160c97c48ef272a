"""The impact law's one home (vibroimpact.dynamics.impact): the constant law, its Python form on other number
types, the results that hold only for it, and another law swapped in for the simulator, Newton's orbits and
the tangent map together."""

import json
import math
import os
import subprocess
import sys
import textwrap

import mpmath as mp
import numpy as np
import pytest

from vibroimpact.dynamics import impact as law
from vibroimpact.dynamics import reference

#: a restitution that falls with the impact speed, r(v) = r0 / (1 + A |v|): the test's other law
A = 0.5


def other_rebound(v, r):
    return -r * v / (1.0 + A * abs(v))


def test_the_constant_law_is_newtons_to_the_last_bit():
    rng = np.random.default_rng(3)
    for v, r in zip(rng.normal(size=50), rng.uniform(0.05, 1.0, 50), strict=True):
        assert law.rebound(v, r) == -r * v
        assert law.rebound_slope(v, r) == -r
    assert law.CONSTANT_RESTITUTION
    assert law.exponent_sum(0.5) == 2 * math.log(0.5)


def test_the_law_works_on_mpmath_numbers_in_the_reference():
    with mp.workdps(40):
        v, r = mp.mpf(1) / 3, mp.mpf("0.5")
        u = reference.rebound(v, r)
        assert isinstance(u, mp.mpf) and u == -r * v  # 40 digits, not a float's 16
        assert abs(u + mp.mpf(1) / 6) < mp.mpf(10) ** -39
        assert reference._slow_restitution(mp.mpf("1e-26"), r) == r


def test_exponent_sum_refuses_a_restitution_outside_its_range():
    with pytest.raises(ValueError, match="r = 1.5"):
        law.exponent_sum(1.5)


SWAP = textwrap.dedent(f"""
    import json, math
    import numpy as np
    from numba import njit
    from vibroimpact.dynamics import impact as law

    @njit(inline="always")
    def rebound(v, r):
        return -r * v / (1.0 + {A} * abs(v))

    @njit(inline="always")
    def rebound_slope(v, r):
        return -r / (1.0 + {A} * abs(v)) ** 2

    # swapped before anything is compiled (the kernels read the law when they compile)
    law.rebound, law.rebound_slope, law.CONSTANT_RESTITUTION = rebound, rebound_slope, False

    import vibroimpact as vi
    from vibroimpact.benchmarks import peer_siconos
    from vibroimpact.dynamics.flight import step_jacobian

    p = vi.Params(d=0.16, gbar=0.24402 * 0.5, r=0.5)
    settle = vi.simulate(p, 1.015, 0.1924, n_impacts=3000, stop_when_periodic=True)
    k = int(np.flatnonzero(settle.v_minus.values > 0.3)[-1])   # the fast bottom impact of the 2:1 it settles on
    o = vi.find_orbit(p, "BBT", float(settle.phase[k]), float(settle.v_minus[k]))
    n = o.n
    run = vi.simulate(p, o.phi, o.v_minus[0], n_impacts=n + 1)
    t, ph, vm, vp = (run[x].values for x in ("t", "phase", "v_minus", "v_plus"))
    product = np.eye(2)
    for j in range(n):
        step = step_jacobian(t[j + 1] - t[j], ph[j], vm[j], vm[j + 1], p.gbar + math.cos(ph[j + 1]), p.r)
        product = np.array(step).reshape(2, 2) @ product

    def period_map(dt, dv):   # (t, Zdot-) of the bottom impact one period on, by the simulator
        nxt = vi.simulate(p, o.phi + math.pi * dt, o.v_minus[0] + dv, n_impacts=n + 1)
        return np.array([nxt.t.values[n] + dt, nxt.v_minus.values[n]])

    h = 1e-6
    fd = np.column_stack([(period_map(h, 0) - period_map(-h, 0)) / (2 * h),
                          (period_map(0, h) - period_map(0, -h)) / (2 * h)])
    refusals = []
    for call in (lambda: law.exponent_sum(p.r), lambda: peer_siconos._call({{}}, 1.0)):
        try:
            call()
        except ValueError as err:
            refusals.append(str(err))
    print(json.dumps(dict(v_orbit=o.v_minus.tolist(), t_orbit=o.t.tolist(), phase_orbit=o.phase.tolist(),
                          v_run=vm.tolist(), v_plus=vp.tolist(), t_run=t.tolist(), phase_run=ph.tolist(),
                          jacobian=o.jacobian.tolist(), product=product.tolist(), fd=fd.tolist(),
                          admissible=bool(o.admissible), refusals=refusals)))
""")


@pytest.fixture(scope="module")
def swapped(tmp_path_factory):
    """The script above in a process of its own, with a numba cache of its own: the kernels compiled with the
    other law never meet the package's cache."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path_factory.mktemp("numba_other_law")))
    out = subprocess.run([sys.executable, "-c", SWAP], capture_output=True, text=True, env=env, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_another_law_is_the_one_the_simulator_applies(swapped):
    vm, vp = np.array(swapped["v_run"]), np.array(swapped["v_plus"])
    np.testing.assert_array_equal(vp, [other_rebound(v, 0.5) for v in vm])
    assert np.ptp(vp / vm) > 0.05  # the restitution does change from impact to impact


def test_the_simulated_run_from_newtons_orbit_returns_to_it(swapped):
    n = len(swapped["v_orbit"])
    assert swapped["admissible"]
    np.testing.assert_allclose(swapped["v_run"][:n], swapped["v_orbit"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(swapped["t_run"][:n], swapped["t_orbit"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(swapped["phase_run"][:n], swapped["phase_orbit"], rtol=0, atol=1e-12)
    # one forcing period later it is back at the orbit's first impact
    assert abs(swapped["t_run"][n] - 2.0) < 1e-12
    assert abs(swapped["v_run"][n] - swapped["v_orbit"][0]) < 1e-12
    assert abs(swapped["phase_run"][n] - swapped["phase_orbit"][0]) < 1e-12


def test_the_monodromy_matrix_is_the_product_of_tangent_steps_and_the_simulators_derivative(swapped):
    J = np.array(swapped["jacobian"])
    np.testing.assert_allclose(swapped["product"], J, rtol=0, atol=1e-11)
    # central differences of the simulator's period map: error h^2 (1e-12) and rounding 1e-16 / h
    np.testing.assert_allclose(swapped["fd"], J, rtol=0, atol=1e-8)
    # the constant law's determinant r^6 v_0 / v_3 = r^6 does not hold for this law
    assert abs(np.linalg.det(J) - 0.5 ** 6) > 1e-3


def test_results_for_a_constant_restitution_refuse_another_law(swapped):
    exponents, siconos = swapped["refusals"]
    assert "not 2 ln r" in exponents
    assert "constant restitution" in siconos
