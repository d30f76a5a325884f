"""The lean kinematics the package binds: body_kinematics and jac_site_from_q give what
kinematics and kinematics + jac_site give, bit for bit (tests/property/poses.cpp holds the C++
calls to every array they write; this holds the bindings to theirs)."""
import numpy as np
import pytest

import lever
from conftest import REPO

MODELS = [REPO / "models" / "panda7.xml", REPO / "tests" / "models" / "sensors.xml"]


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_lean_kinematics_bit_for_bit(path):
    model = lever.load(str(path))
    rng = np.random.default_rng(7)
    full, lean = lever.Data(model), lever.Data(model)
    for _ in range(3):
        qpos = rng.uniform(-1, 1, model.nq)
        for d in (full, lean):
            d.qpos[:] = qpos
        lever.kinematics(model, full)
        lever.body_kinematics(model, lean)
        for name in ("xpos", "xmat", "xipos", "ximat", "subtree_com", "cdof"):
            assert np.array_equal(getattr(lean, name), getattr(full, name)), name
        assert model.nsite > 0
        for site in range(model.nsite):
            jacp, jacr = lever.jac_site(model, full, site)
            lean.qpos[:] = qpos  # as given: normalizing a quaternion twice may move its last bit
            lean_jacp, lean_jacr = lever.jac_site_from_q(model, lean, site)
            assert np.array_equal(lean_jacp, jacp) and np.array_equal(lean_jacr, jacr)
            assert np.array_equal(lean.site_xpos[site], full.site_xpos[site])
    with pytest.raises(lever.StateError, match="jac_site_from_q: site"):
        lever.jac_site_from_q(model, lean, model.nsite)
