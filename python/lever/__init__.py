"""lever: rigid-body dynamics for robot arms, proven against MuJoCo 2.2.2.

The C++ library seen from Python. Model and Data arrays are numpy views of lever's own memory
(zero-copy): ``data.qpos[:] = q`` sets the state lever evaluates.

    import lever
    model = lever.load("models/arm2.xml")     # raises lever.ParseError with file and line
    data = lever.Data(model)
    data.qpos[:] = [0.6, -1.2]
    lever.forward(model, data)                # data.qfrc_bias, data.M, data.site_xpos, ...
    for _ in range(500):
        lever.step(model, data)
    report = lever.check(model)               # lesson 5.1's six checks, as a dict
    runner = lever.BatchRunner(model, threads=2)  # many states at once, on two threads
    out = runner.forward(qpos, qvel, fields=("qacc", "site_xpos"))  # qpos (n, nq): a state a row
    qpos2, qvel2 = runner.step(qpos, qvel, nstep=10)                # out["qacc"]: (n, nv)

For programs written against MuJoCo's Python bindings, ``import lever.mujoco as mujoco``.
"""

import json as _json
import os as _os

from ._lever import (  # noqa: F401  (the package's API)
    BatchRunner,
    Data,
    Error,
    Model,
    ModelError,
    ParseError,
    StateError,
    __version__,
    actuation,
    bias,
    body_kinematics,
    compute_energy,
    contact_force,
    contact_members,
    copy_model,
    crba,
    data_field_table,
    factor_mass,
    forward,
    forward_derivatives,
    inverse,
    jac_point,
    jac_site,
    jac_site_from_q,
    kinematics,
    load,
    load_string,
    model_parameters,
    model_field_table,
    passive,
    regressor,
    regressor_names,
    reset,
    rnea,
    set_const,
    solve_mass,
    step,
    step_all,
    step_derivatives,
    step1,
    step2,
    transmission,
    reset_keyframe,
)
from . import _lever


def derivatives(model: Model, data: Data) -> dict:
    """The analytic derivatives of the step and of forward dynamics at data's state, through
    contacts and joint limits with their active set held (docs/derivatives.md), as
    `lever derivatives --json` prints them. data's state is left as it was (its other fields hold
    forward() at that state).

    Returns a dict of numpy arrays: ``A`` (2nv + na square) and ``B`` (2nv + na x nu), the
    step's Jacobians in mjd_transitionFD's layout (x = [dq; qvel; act], dq qpos's tangent: nv
    numbers, act the stateful actuators' activations);
    ``dqacc_dq``, ``dqacc_dv`` (nv x nv), ``dqacc_du`` (nv x nu), ``dqacc_dact`` (nv x na,
    d qacc / d act: the activations' columns, empty when na is 0) and ``dqacc_dapplied``
    (nv x nv, d qacc / d qfrc_applied), forward dynamics at the state; ``nefc``; and
    ``active_set_changes``: True when the constraint rows' active set (which contacts exist, which
    rows push, which geoms a spatial tendon wraps and which way round) is not the same at the
    step's end (or an RK4 stage) as at its start, so that A and B are the start's piece held, not
    the derivative a difference across the step would see. Then a RuntimeWarning says so too.

    Raises lever.Error naming what it does not differentiate (an integrator, a contact pair's
    geometry, an elliptic cone on its surface, equality constraints, friction loss).
    """
    out = _lever.derivatives(model, data)
    if out["active_set_changes"]:
        import warnings as _warnings
        _warnings.warn("lever.derivatives: the constraint rows' active set changes within the step "
                       "(or a spatial tendon's wrapping does); A and B hold the start's "
                       "(docs/derivatives.md)", RuntimeWarning,
                       stacklevel=2)
    return out


def check(model: Model, key: str = "") -> dict:
    """Lesson 5.1's six checks of a model, lesson 5.2's two and lesson 5.3's contacts: the report
    `lever check --json` prints, as a dict.

    Its keys are the sections (``structure``, ``kinematics``, ``torque_budget``, ``inertia``,
    ``soft_stops``, ``clamping``, ``singular_poses``, ``step_stability``, ``contacts``), ``findings`` (the
    claims that do not check out) and ``exit_status`` (0 when every claim checks out). ``key``:
    sections 7 and 8 at that keyframe only (`lever check --key`).
    """
    return _json.loads(_lever.check_json(model, key))


def check_text(model: Model, key: str = "") -> str:
    """The same checks as the text `lever check` prints."""
    return _lever.check_text(model, key)


def lab_run(model: Model, data: Data, torque, gravity_compensation: bool = False,
            steps: int = 1, on_row=None) -> dict:
    """Lesson 5.1's lab: ``ctrl = torque + (qfrc_bias / gear if gravity_compensation)``, then a
    step, ``steps`` times. ``on_row(row, data)`` sees the start state and every state after a step.
    Returns the clamped-step count per motor, the engine's warnings and the non-finite rows."""
    import numpy as _np
    return _lever.lab_run(model, data, _np.asarray(torque, dtype=float), bool(gravity_compensation),
                          int(steps), on_row)


def identify(prior, trajectory, gains=None, known_masses=None, write_model=None) -> dict:
    """Identify a model's inertial parameters (and armature, damping, gains) from a trajectory,
    as `lever identify` does (docs/derivatives.md).

    ``prior``: a Model (or a model file's path) whose kinematics are right. ``trajectory``: a CSV
    file in `lever simulate --csv`'s columns, or a dict of arrays with one row per sample:
    ``time`` (N), ``qpos`` (N, nq), ``qvel`` and ``qacc`` (N, nv), and either ``qfrc`` (N, nv: the
    joint force of the motors, the user and the stops) or ``actuator_force`` (N, nu; with an
    optional ``qfrc_constraint`` (N, nv)); ``ctrl`` (N, nu) when gains are estimated.
    ``gains``: actuator names (or "all") whose gain is estimated from ctrl. ``known_masses``:
    {body: kg}, a body whose mass is known (its shape the prior's). ``write_model``: write the
    identified model as MJCF there (the prior must come from a file).

    Returns a dict: ``names``, ``prior``, ``estimate`` and ``standard_error`` (one per base
    parameter), ``physical_estimate`` and ``estimate_physical`` (whether the least-squares
    estimate is a rigid-body model's; if not, the physical fit nearest it),
    ``residual_rms`` and ``physical_residual_rms``, ``distance_to_prior`` (per body), ``parameters``
    (the full pi written), ``unexcited``, ``not_physical`` (None or why), ``model`` (the identified
    lever.Model, None if not physical) and ``written`` (the path, or None).
    """
    if isinstance(prior, (str, _os.PathLike)):
        prior = load(_os.fspath(prior))
    if isinstance(trajectory, _os.PathLike):
        trajectory = _os.fspath(trajectory)
    if isinstance(gains, (list, tuple)):
        gains = ",".join(gains)
    known = [f"{name}={float(kg)!r}" for name, kg in (known_masses or {}).items()]
    return _lever.identify(prior, trajectory, gains or "", known,
                           _os.fspath(write_model) if write_model else "")
