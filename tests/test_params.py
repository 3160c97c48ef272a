import math

import pytest

import vibroimpact as vi


def test_paper_scaling_of_d_and_gbar():
    # docs/guide/model.md: d = 0.6225 s and gbar = 0.24402 sin(beta) with the paper's defaults
    p = vi.Params.from_physical(s=1.0, beta=math.pi / 2)
    assert p.d == pytest.approx(0.6225, abs=5e-5)
    assert p.gbar == pytest.approx(0.24402, abs=5e-6)
    q = vi.Params.from_physical(s=0.3, beta=math.pi / 6)
    assert q.d == pytest.approx(0.6225 * 0.3, rel=1e-4)
    assert q.gbar == pytest.approx(0.24402 / 2, rel=1e-4)


def test_scales_convert_back_to_physical_units():
    p = vi.Params.from_physical(s=0.5, beta=math.pi / 3)
    # length scale times d is the physical length s
    assert p.scales.length * p.d == pytest.approx(0.5, rel=1e-12)
    assert p.scales.time == pytest.approx(1 / 5)  # pi / omega with omega = 5 pi
    assert p.scales.velocity == pytest.approx(5.0 * math.pi / (0.1245 * 5 * math.pi))


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(d=0.0, gbar=0.1, r=0.5), "d"),
        (dict(d=-1, gbar=0.1, r=0.5), "d"),
        (dict(d=0.2, gbar=-0.1, r=0.5), "gbar"),
        (dict(d=0.2, gbar=0.1, r=1.0), "r"),
        (dict(d=0.2, gbar=0.1, r=-0.1), "r"),
        (dict(d=float("nan"), gbar=0.1, r=0.5), "d"),
        (dict(d="abc", gbar=0.1, r=0.5), "d"),
    ],
)
def test_invalid_parameters_name_key_value_and_range(kwargs, name):
    with pytest.raises(ValueError) as err:
        vi.Params(**kwargs)
    msg = str(err.value)
    assert msg.startswith(f"{name} = ")
    assert "allowed" in msg


@pytest.mark.parametrize("kwargs, name", [(dict(s=0.0, beta=1.0), "s"), (dict(s=0.3, beta=2.0), "beta"),
                                          (dict(s=0.3, beta=1.0, F=0), "F"), (dict(s=0.3, beta=1.0, M=-1), "M"),
                                          (dict(s=0.3, beta=1.0, omega=0), "omega")])
def test_invalid_physical_parameters(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name} = .*allowed"):
        vi.Params.from_physical(**kwargs)


def test_gbar_at_least_one_is_legal_and_flagged():
    assert vi.Params(d=0.2, gbar=1.0, r=0.5).never_leaves_bottom
    assert not vi.Params(d=0.2, gbar=0.99, r=0.5).never_leaves_bottom
