"""Refusals come early and name the value: a law with a bad value or an unknown parameter is
refused where it is written, not where it is first bound; a normal that is not a unit vector
is refused by every law that takes one; a stiffness too large for its law's arithmetic is
refused rather than returned as an infinite force."""

import numpy as np
import pytest

import dashpot
from conftest import M_PAIR, MCC, R_PAIR


def test_a_bad_value_or_name_is_refused_at_construction_not_at_bind():
    with pytest.raises(ValueError, match=r"'eps' of law 'hsd' = 1\.7 is out of range: valid values are \(0, 1\]"):
        dashpot.ContactLaw("hsd", eps=1.7)
    with pytest.raises(ValueError, match=r"has no parameter 'esp'.*did you mean `eps`"):
        dashpot.ContactLaw("hsd", esp=0.5)
    with pytest.raises(ValueError, match="unknown law 'hds'"):
        dashpot.ContactLaw("hds", eps=0.5)
    # a law of another kind, named by its own kind
    with pytest.raises(ValueError, match="'mindlin' is a tangential law, but a contact law"):
        dashpot.ContactLaw("mindlin", mu=0.3)
    with pytest.raises(ValueError, match=r"'mu' of law 'mindlin' = -1"):
        dashpot.TangentialLaw("mindlin", mu=-1.0)
    with pytest.raises(ValueError, match="has no parameter"):
        dashpot.RollingLaw("rolling-sds", stiffness=1.0)
    with pytest.raises(ValueError, match="has no parameter"):
        dashpot.TwistingLaw("twisting-sds", stiffness=1.0)
    with pytest.raises(ValueError, match="has no parameter"):
        dashpot.RestitutionLaw("mcnamara-falcon", bogus=1.0)
    # good values construct and bind as before
    assert dashpot.ContactLaw("hsd", eps=0.5).bind(**MCC).name == "hsd"


@pytest.mark.parametrize("kind,law", [(dashpot.TangentialLaw, "mindlin"), (dashpot.TangentialLaw, "linear-history"),
                                      (dashpot.RollingLaw, "rolling-sds"), (dashpot.RollingLaw, "rolling-epsd")])
def test_a_normal_that_is_not_a_unit_vector_is_refused(kind, law):
    b = kind(law).bind(**MCC)
    v, fn, d, m, r = [[0.1, 0.0, 0.0]], [1.0], [1e-6], [M_PAIR], [R_PAIR]
    for bad in ([0.0, 0.0, 0.0], [0.0, 0.0, 2.0], [0.0, 0.0, np.nan]):
        h = np.zeros((1, b.history_slots))
        with pytest.raises(ValueError, match=r"normal of contact 0 .* unit vector"):
            b.force(1e-6, [bad], v, fn, d, m, r, h)
        assert not h.any(), "a refused call must leave the history as it was"
    # the unit normal: a force against the motion, in the tangent plane
    h = np.zeros((1, b.history_slots))
    f = b.force(1e-6, [[0.0, 0.0, 1.0]], v, fn, d, m, r, h)
    assert f[0, 0] < 0.0 and f[0, 2] == 0.0


def test_twisting_refuses_a_zero_normal():
    b = dashpot.TwistingLaw("twisting-sds").bind(**MCC)
    h = np.zeros((1, b.history_slots))
    with pytest.raises(ValueError, match=r"normal of contact 0 .* unit vector"):
        b.torque(1e-6, [[0.0, 0.0, 0.0]], [1.0], [1.0], [1e-6], [M_PAIR], [R_PAIR], h)


def test_a_stiffness_whose_force_overflows_is_an_exception_not_inf():
    b = dashpot.ContactLaw("lsd", k=1e308, eps=0.5).bind(**MCC)
    with pytest.raises((ValueError, RuntimeError), match="inf|finite"):
        b.force([10.0], [0.1], [M_PAIR], [R_PAIR])


def test_friction_with_an_enormous_stiffness_still_caps_at_coulomb():
    """kt = 1e300 N/m: the spring saturates at once and the force is the cap μ F_n, not 0."""
    b = dashpot.TangentialLaw("linear-history", kt=1e300, mu=0.3).bind(**MCC)
    h = np.zeros((1, b.history_slots))
    f = b.force(1e-6, [[0.0, 0.0, 1.0]], [[0.1, 0.0, 0.0]], [10.0], [1e-6], [M_PAIR], [R_PAIR], h)
    assert f[0, 0] == pytest.approx(-3.0, rel=1e-12) and f[0, 1] == 0.0 and f[0, 2] == 0.0
