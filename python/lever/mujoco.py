"""lever.mujoco: MuJoCo's Python API (3.x names) over what lever computes.

A program written for MuJoCo's Python bindings runs on lever with one changed import::

    import lever.mujoco as mujoco

It covers lever's features: models of hinge, slide, ball and free joints, motors, joint limits,
sites and contacts (d.ncon, d.contact, the efc arrays, mj_contactForce); the forward pipeline,
the split step, inverse dynamics, M and its products, Jacobians, energies and names. Every mjModel/mjData array lever has keeps MuJoCo's name, shape and dtype and is a writable
view of lever's memory (``model.body_mass[2] = 1.6`` then ``mj_setConst``). Whatever MuJoCo has
and lever does not raises NotImplementedError naming it, never a silent wrong value; a name that
MuJoCo does not have either raises AttributeError, and an unknown object name raises KeyError.
"""

import enum as _enum
import os as _os

import numpy as _np

from . import _lever
from . import _mujoco_names

__all__ = [
    "MjModel", "MjData", "mjtObj", "mjtConstraint", "mjtConstraintState", "mjtIntegrator",
    "mj_forward", "mj_step", "mj_step1", "mj_step2", "mj_kinematics", "mj_comPos", "mj_crb",
    "mj_factorM", "mj_rne", "mj_inverse", "mj_fullM", "mj_mulM", "mj_solveM", "mj_jacSite",
    "mj_jacBody", "mj_jac", "mj_integratePos", "mj_differentiatePos", "mj_setConst", "mj_resetData", "mj_resetDataKeyframe",
    "mj_name2id", "mj_id2name", "mj_energyPos", "mj_energyVel", "mj_contactForce",
]

mjVERSION_HEADER = 222  # the MuJoCo version lever is proven against


class mjtObj(_enum.IntEnum):
    """Object types (MuJoCo's mjtObj values)."""
    mjOBJ_UNKNOWN = 0
    mjOBJ_BODY = 1
    mjOBJ_XBODY = 2
    mjOBJ_JOINT = 3
    mjOBJ_DOF = 4
    mjOBJ_GEOM = 5
    mjOBJ_SITE = 6
    mjOBJ_CAMERA = 7
    mjOBJ_LIGHT = 8
    mjOBJ_MESH = 9
    mjOBJ_SKIN = 10
    mjOBJ_HFIELD = 11
    mjOBJ_TEXTURE = 12
    mjOBJ_MATERIAL = 13
    mjOBJ_PAIR = 14
    mjOBJ_EXCLUDE = 15
    mjOBJ_EQUALITY = 16
    mjOBJ_TENDON = 17
    mjOBJ_ACTUATOR = 18
    mjOBJ_SENSOR = 19
    mjOBJ_NUMERIC = 20
    mjOBJ_TEXT = 21
    mjOBJ_TUPLE = 22
    mjOBJ_KEY = 23


class mjtConstraint(_enum.IntEnum):
    """Constraint types (mjtConstraint); lever makes joint-limit and contact rows."""
    mjCNSTR_EQUALITY = 0
    mjCNSTR_FRICTION_DOF = 1
    mjCNSTR_FRICTION_TENDON = 2
    mjCNSTR_LIMIT_JOINT = 3
    mjCNSTR_LIMIT_TENDON = 4
    mjCNSTR_CONTACT_FRICTIONLESS = 5
    mjCNSTR_CONTACT_PYRAMIDAL = 6
    mjCNSTR_CONTACT_ELLIPTIC = 7


class mjtConstraintState(_enum.IntEnum):
    """Constraint row states (mjtConstraintState)."""
    mjCNSTRSTATE_SATISFIED = 0
    mjCNSTRSTATE_QUADRATIC = 1
    mjCNSTRSTATE_LINEARNEG = 2
    mjCNSTRSTATE_LINEARPOS = 3
    mjCNSTRSTATE_CONE = 4


class mjtIntegrator(_enum.IntEnum):
    """Integrators (mjtIntegrator): lever has all three of MuJoCo 2.2.2's."""
    mjINT_EULER = 0
    mjINT_RK4 = 1
    mjINT_IMPLICIT = 2


# lever's arrays that MuJoCo has under the same name, shape and meaning (the field table)
_MODEL_FIELDS = frozenset(f["name"] for f in _lever.model_field_table() if f["mujoco"])
_DATA_FIELDS = frozenset(f["name"] for f in _lever.data_field_table() if f["mujoco"])
_SIZES = ("nq", "nv", "nu", "nbody", "njnt", "ngeom", "nsite", "npair", "nexclude", "nmocap",
          "nconmax", "njmax")
# keyframe arrays lever has, as MuJoCo's (nkey rows)
_KEY_FIELDS = ("key_time", "key_qpos", "key_qvel", "key_ctrl", "key_mpos", "key_mquat")


def _missing(kind: str, name: str):
    """The error for a MuJoCo name lever lacks, or a name MuJoCo lacks too."""
    if name in getattr(_mujoco_names, kind):
        return NotImplementedError(
            f"lever.mujoco: {'mjModel' if kind == 'MODEL' else 'mjData'}.{name} is MuJoCo's but "
            f"lever does not compute it (lever covers hinge and slide joints, motors, joint "
            f"limits and sites; see docs/python.md)")
    return AttributeError(f"'{'MjModel' if kind == 'MODEL' else 'MjData'}' object has no "
                          f"attribute '{name}'")


# ---- named access: model.joint('elbow').axis, data.site('ee').xpos -------------------------------

# object type -> (name list in lever's Model, prefix of its model arrays, size attribute)
_OBJECTS = {
    "body": ("body_name", "body_", "nbody"),
    "joint": ("jnt_name", "jnt_", "njnt"),
    "geom": ("geom_name", "geom_", "ngeom"),
    "site": ("site_name", "site_", "nsite"),
    "actuator": ("actuator_name", "actuator_", "nu"),
}
_OBJ_TYPES = {
    mjtObj.mjOBJ_BODY: "body", mjtObj.mjOBJ_XBODY: "body", mjtObj.mjOBJ_JOINT: "joint",
    mjtObj.mjOBJ_GEOM: "geom", mjtObj.mjOBJ_SITE: "site", mjtObj.mjOBJ_ACTUATOR: "actuator",
}

# data arrays reachable from a named object, as MuJoCo's accessors name them: attribute ->
# (data array, how the object's index maps to its rows)
_DATA_ACCESS = {
    "body": {"xpos": "xpos", "xquat": "xquat", "xmat": "xmat", "xipos": "xipos",
             "ximat": "ximat", "subtree_com": "subtree_com", "cvel": "cvel"},
    "joint": {"qpos": "qpos", "qvel": "qvel", "qacc": "qacc", "qfrc_applied": "qfrc_applied",
              "qfrc_bias": "qfrc_bias", "qfrc_passive": "qfrc_passive",
              "qfrc_actuator": "qfrc_actuator", "qfrc_constraint": "qfrc_constraint",
              "qfrc_smooth": "qfrc_smooth", "qacc_smooth": "qacc_smooth",
              "qfrc_inverse": "qfrc_inverse", "xanchor": "xanchor", "xaxis": "xaxis",
              "cdof": "cdof", "cdof_dot": "cdof_dot"},
    "site": {"xpos": "site_xpos", "xmat": "site_xmat"},
    "actuator": {"ctrl": "ctrl", "force": "actuator_force", "length": "actuator_length",
                 "velocity": "actuator_velocity"},
    "geom": {},
}
_MUJOCO_DATA_ACCESS = {  # what MuJoCo's accessors also have that lever does not compute
    "body": {"xfrc_applied", "cinert", "cacc", "cfrc_int", "cfrc_ext", "crb"},
    "joint": {"qLDiagInv", "qacc_warmstart"},
    "site": set(),
    "actuator": {"act", "act_dot", "moment"},
    "geom": {"xpos", "xmat"},
}


def _row(array: _np.ndarray, i: int) -> _np.ndarray:
    """One object's row as a view; one-number rows as shape (1,), as MuJoCo's accessors give."""
    return array[i] if array.ndim == 2 else array[i:i + 1]


# coordinates (qpos) and dofs (qvel) of each joint type, by MuJoCo's mjtJoint value: free, ball,
# slide, hinge
_JOINT_NQ = (7, 4, 1, 1)
_JOINT_NV = (6, 3, 1, 1)


def _joint_slice(array: _np.ndarray, native, joint: int, coordinates: bool) -> _np.ndarray:
    """A joint's entries of a qpos-sized (coordinates) or qvel-sized array, as a view."""
    kind = int(native.jnt_type[joint])
    adr = int((native.jnt_qposadr if coordinates else native.jnt_dofadr)[joint])
    return array[adr:adr + (_JOINT_NQ if coordinates else _JOINT_NV)[kind]]


def _resolve(native, kind: str, key) -> int:
    names_attr, _, size_attr = _OBJECTS[kind]
    names = getattr(native, names_attr)
    if isinstance(key, str):
        try:
            return names.index(key)
        except ValueError:
            valid = [n for n in names if n]
            raise KeyError(f"Invalid name '{key}'. Valid names: {valid}") from None
    index = int(key)
    n = getattr(native, size_attr)
    if not 0 <= index < n:
        raise IndexError(f"Invalid index {index} for a {kind}: there are {n}")
    return index


class _ModelObject:
    """model.body(...), model.joint(...), ...: the object's rows of the model arrays."""

    def __init__(self, model: "MjModel", kind: str, key):
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_kind", kind)
        object.__setattr__(self, "id", _resolve(model._native, kind, key))
        names = getattr(model._native, _OBJECTS[kind][0])
        object.__setattr__(self, "name", names[self.id])

    def _array(self, attr: str) -> _np.ndarray:
        kind, model = self._kind, self._model
        full = _OBJECTS[kind][1] + attr
        if kind == "joint" and attr in ("qpos0", "qpos_spring"):
            return _joint_slice(getattr(model._native, attr), model._native, self.id, True)
        if kind == "joint" and attr in ("armature", "damping", "invweight0", "M0"):
            return _joint_slice(getattr(model._native, "dof_" + attr), model._native, self.id,
                                False)
        if full in _MODEL_FIELDS or full == "actuator_trnid":
            return _row(getattr(model, full), self.id)
        raise _missing("MODEL", full) if full in _mujoco_names.MODEL else AttributeError(
            f"a model {kind} has no attribute '{attr}'")

    def __getattr__(self, attr: str):
        return self._array(attr)

    def __setattr__(self, attr: str, value) -> None:
        self._array(attr)[...] = value

    def __repr__(self) -> str:
        return f"<{self._kind} {self.id} '{self.name}'>"


class _DataObject:
    """data.body(...), data.site(...), ...: the object's rows of the data arrays."""

    def __init__(self, data: "MjData", kind: str, key):
        object.__setattr__(self, "_data", data)
        object.__setattr__(self, "_kind", kind)
        native_model = data._model._native
        object.__setattr__(self, "id", _resolve(native_model, kind, key))
        names = getattr(native_model, _OBJECTS[kind][0])
        object.__setattr__(self, "name", names[self.id])

    def _array(self, attr: str) -> _np.ndarray:
        kind, data = self._kind, self._data
        source = _DATA_ACCESS[kind].get(attr)
        if source is None:
            if attr in _MUJOCO_DATA_ACCESS[kind]:
                raise NotImplementedError(f"lever.mujoco: data.{kind}(...).{attr} is MuJoCo's "
                                          f"but lever does not compute it")
            raise AttributeError(f"a data {kind} has no attribute '{attr}'")
        array = getattr(data, source)
        if kind == "joint" and source not in ("xanchor", "xaxis"):
            # a ball's qpos is its quaternion (4), its qvel three rates; a free joint's 7 and 6
            return _joint_slice(array, data._model._native, self.id, source == "qpos")
        return _row(array, self.id)

    def __getattr__(self, attr: str):
        return self._array(attr)

    def __setattr__(self, attr: str, value) -> None:
        self._array(attr)[...] = value

    def __repr__(self) -> str:
        return f"<data {self._kind} {self.id} '{self.name}'>"


# ---- MjModel, MjOption, MjData -------------------------------------------------------------------

class MjOption:
    """model.opt: timestep, gravity and integrator, written through to lever's model."""

    def __init__(self, native):
        object.__setattr__(self, "_native", native)

    @property
    def timestep(self) -> float:
        return self._native.timestep

    @timestep.setter
    def timestep(self, value: float) -> None:
        self._native.timestep = float(value)

    @property
    def gravity(self) -> _np.ndarray:
        return self._native.gravity

    @gravity.setter
    def gravity(self, value) -> None:
        self._native.gravity[:] = value

    @property
    def integrator(self) -> int:
        return self._native.integrator

    @integrator.setter
    def integrator(self, value: int) -> None:
        self._native.integrator = int(value)  # Euler, RK4 or implicit (MuJoCo 2.2.2's)

    def __getattr__(self, name: str):
        if name in _mujoco_names.OPTION:
            raise NotImplementedError(f"lever.mujoco: mjOption.{name} is MuJoCo's but lever "
                                      f"does not use it")
        raise AttributeError(f"'MjOption' object has no attribute '{name}'")

    def __setattr__(self, name: str, value) -> None:
        if name in ("timestep", "gravity", "integrator"):
            object.__setattr__(self, name, value)
        else:
            self.__getattr__(name)


class MjModel:
    """A compiled model, as mujoco.MjModel: from_xml_path, from_xml_string, the arrays by name,
    named access (model.joint('elbow').axis), and model.opt."""

    def __init__(self, native):
        object.__setattr__(self, "_native", native)
        object.__setattr__(self, "opt", MjOption(native))

    @staticmethod
    def from_xml_path(filename, assets=None) -> "MjModel":
        if assets:
            raise NotImplementedError("lever.mujoco: MjModel.from_xml_path with assets")
        return MjModel(_lever.load(_os.fspath(filename)))

    @staticmethod
    def from_xml_string(xml: str, assets=None) -> "MjModel":
        if assets:
            raise NotImplementedError("lever.mujoco: MjModel.from_xml_string with assets")
        return MjModel(_lever.load_string(xml))

    @property
    def nkey(self) -> int:
        return self._native.nkey

    @property
    def actuator_trnid(self) -> _np.ndarray:
        """(nu, 2) as MuJoCo's: the joint, then -1 (a joint transmission has no second id)."""
        out = _np.full((self._native.nu, 2), -1, dtype=_np.int32)
        out[:, 0] = self._native.actuator_trnid
        out.flags.writeable = False
        return out

    def __getattr__(self, name: str):
        native = object.__getattribute__(self, "_native")
        if name in _MODEL_FIELDS or name in _SIZES or name in _KEY_FIELDS:
            return getattr(native, name)
        raise _missing("MODEL", name)

    def __setattr__(self, name: str, value) -> None:
        if name in _MODEL_FIELDS or name in _KEY_FIELDS:
            getattr(self._native, name)[...] = value
        elif name in _SIZES:
            raise AttributeError(f"MjModel.{name} cannot be set")
        else:
            raise _missing("MODEL", name)

    def __repr__(self) -> str:
        return f"<lever.mujoco.MjModel {self._native.name!r} nq={self.nq} nu={self.nu}>"


# ---- contacts (issue 19): d.contact as MuJoCo's bindings show it -------------------------------

class _MjContact:
    """One contact (MuJoCo's MjContact): pos (3,), frame (9,: normal, then two tangents), dist,
    geom1, geom2, dim, friction (5,), solref (2,), solimp (5,), includemargin, exclude,
    efc_address, mu. Arrays are views of lever's memory; numbers are read when asked for."""

    def __init__(self, native, index: int):
        object.__setattr__(self, "_native", native)
        object.__setattr__(self, "_index", index)

    def __getattr__(self, name: str):
        if name not in _CONTACT_MEMBERS:
            raise AttributeError(f"'MjContact' object has no attribute '{name}'")
        value = self._native.contact_field(name)[self._index]
        return value if _np.ndim(value) else value.item()

    def __setattr__(self, name: str, value) -> None:
        raise AttributeError(f"lever.mujoco: MjContact.{name} is computed by mj_forward; it "
                             f"cannot be set")

    def __repr__(self) -> str:
        return (f"<MjContact geom1={self.geom1} geom2={self.geom2} dist={self.dist:g} "
                f"dim={self.dim}>")


class _MjContactList:
    """d.contact: len() is ncon; d.contact[i] is one contact; d.contact.dist and the other members
    are arrays over the ncon contacts (views, shape (ncon,) or (ncon, k)), as MuJoCo's."""

    def __init__(self, native):
        object.__setattr__(self, "_native", native)

    def __len__(self) -> int:
        return self._native.ncon

    def __getitem__(self, index) -> _MjContact:
        n = self._native.ncon
        i = int(index)
        if i < 0:
            i += n
        if not 0 <= i < n:
            raise IndexError(f"contact index {index} out of range: ncon is {n}")
        return _MjContact(self._native, i)

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def __getattr__(self, name: str) -> _np.ndarray:
        if name not in _CONTACT_MEMBERS:
            raise AttributeError(f"'MjContactList' object has no attribute '{name}'")
        return self._native.contact_field(name)


_CONTACT_MEMBERS = frozenset(_lever.contact_members())


class MjData:
    """The state and outputs, as mujoco.MjData(model)."""

    def __init__(self, model: MjModel):
        if not isinstance(model, MjModel):
            raise TypeError("MjData(model) needs a lever.mujoco.MjModel")
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_native", _lever.Data(model._native))

    @property
    def model(self) -> MjModel:
        return self._model

    @property
    def time(self) -> float:
        return self._native.time

    @time.setter
    def time(self, value: float) -> None:
        self._native.time = float(value)

    @property
    def nefc(self) -> int:
        return self._native.nefc

    @property
    def efc_J(self) -> _np.ndarray:
        """(nefc, nv): the constraint Jacobian's live rows, dense (MuJoCo's dense layout)."""
        return self._native.efc_J

    @property
    def contact(self) -> "_MjContactList":
        """The first ncon contacts, as MuJoCo's d.contact: d.contact.dist (ncon,), d.contact[i]."""
        return _MjContactList(self._native)

    @property
    def ne(self) -> int:
        return 0

    @property
    def nf(self) -> int:
        return 0

    @property
    def ncon(self) -> int:
        return self._native.ncon

    def __getattr__(self, name: str):
        native = object.__getattribute__(self, "_native")
        if name in _DATA_FIELDS:
            return getattr(native, name)
        raise _missing("DATA", name)

    def __setattr__(self, name: str, value) -> None:
        if name in _DATA_FIELDS:
            getattr(self._native, name)[...] = value
        elif name == "time":
            object.__setattr__(self, name, value)
        elif name in ("ncon", "contact", "efc_J", "nefc"):
            raise AttributeError(f"MjData.{name} is computed by mj_forward; it cannot be set")
        else:
            raise _missing("DATA", name)

    def __repr__(self) -> str:
        return f"<lever.mujoco.MjData time={self.time:g} nefc={self.nefc}>"


def _add_named_access(cls, view) -> None:
    """cls.body(key), cls.joint(key) (also cls.jnt), ...: `view(self, kind, key)` for each kind of
    object, as MuJoCo's bindings name its accessors."""
    for kind in ("body", "joint", "geom", "site", "actuator"):
        setattr(cls, kind, lambda self, key, kind=kind: view(self, kind, key))
    cls.jnt = cls.joint


_add_named_access(MjModel, _ModelObject)
_add_named_access(MjData, _DataObject)


# ---- functions -----------------------------------------------------------------------------------

def _pair(m: MjModel, d: MjData):
    if not isinstance(m, MjModel) or not isinstance(d, MjData):
        raise TypeError("expected (MjModel, MjData)")
    if d._model is not m:
        raise ValueError("this MjData was made from another MjModel")
    return m._native, d._native


def mj_forward(m: MjModel, d: MjData) -> None:
    """Everything at the current state."""
    _lever.forward(*_pair(m, d))


def mj_step(m: MjModel, d: MjData, nstep: int = 1) -> None:
    """`nstep` steps of the model's integrator. Afterwards d holds the forward quantities of the
    state before the last step and the new qpos, qvel and time, as in MuJoCo."""
    model, data = _pair(m, d)
    for _ in range(int(nstep)):
        _lever.step_all(model, data)  # lever.step skips xquat and unneeded geom frames


def mj_step1(m: MjModel, d: MjData) -> None:
    _lever.step1(*_pair(m, d))


def mj_step2(m: MjModel, d: MjData) -> None:
    _lever.step2(*_pair(m, d))


def mj_kinematics(m: MjModel, d: MjData) -> None:
    """Poses of bodies, joints and sites (lever computes the com-frame quantities with them)."""
    _lever.kinematics(*_pair(m, d))


def mj_comPos(m: MjModel, d: MjData) -> None:
    """subtree_com, cdof and the spatial inertias (lever's kinematics computes them)."""
    _lever.kinematics(*_pair(m, d))


def mj_crb(m: MjModel, d: MjData) -> None:
    """M(q), armature included (read it with mj_fullM)."""
    _lever.crba(*_pair(m, d))


def mj_factorM(m: MjModel, d: MjData) -> None:
    _lever.factor_mass(*_pair(m, d))


def mj_rne(m: MjModel, d: MjData, flg_acc: int, result: _np.ndarray) -> None:
    """result = C(q, qvel) qvel + g(q), plus M(q) qacc without armature when flg_acc, as
    MuJoCo's RNE (armature is not a body's inertia). Leaves d's arrays as they were."""
    model, data = _pair(m, d)
    if flg_acc:
        tau = _lever.rnea(model, data, data.qacc) - model.dof_armature * data.qacc
    else:
        saved = data.qfrc_bias.copy()
        _lever.bias(model, data)
        tau = data.qfrc_bias.copy()
        data.qfrc_bias[:] = saved
    result[...] = tau


def mj_inverse(m: MjModel, d: MjData) -> None:
    """qfrc_inverse: the force that produces d.qacc at the current state."""
    _lever.inverse(*_pair(m, d))


def mj_fullM(m: MjModel, *args) -> None:
    """mj_fullM(model, data, dst) (MuJoCo 3.10+): dst = M(q) as a dense nv x nv matrix."""
    if len(args) != 2 or not isinstance(args[0], MjData):
        raise NotImplementedError("lever.mujoco: mj_fullM(model, dst, qM) reads MuJoCo's sparse "
                                  "qM, which lever does not keep; call mj_fullM(model, data, dst)")
    d, dst = args
    _pair(m, d)
    dst[...] = d._native.M.reshape(_np.shape(dst))


def mj_mulM(m: MjModel, d: MjData, res: _np.ndarray, vec: _np.ndarray) -> None:
    """res = M vec."""
    _pair(m, d)
    res[...] = d._native.M @ _np.asarray(vec, dtype=float)


def mj_solveM(m: MjModel, d: MjData, x: _np.ndarray, y: _np.ndarray) -> None:
    """x = M^-1 y with the current factor; y may hold several vectors as rows."""
    model, data = _pair(m, d)
    rows = _np.atleast_2d(_np.asarray(y, dtype=float))
    out = _np.array([_lever.solve_mass(model, data, row) for row in rows])
    x[...] = out.reshape(_np.shape(x))


def _write_jacobians(jacp, jacr, jp, jr) -> None:
    if jacp is not None:
        jacp[...] = jp.reshape(_np.shape(jacp))
    if jacr is not None:
        jacr[...] = jr.reshape(_np.shape(jacr))


def mj_jacSite(m: MjModel, d: MjData, jacp, jacr, site: int) -> None:
    model, data = _pair(m, d)
    _write_jacobians(jacp, jacr, *_lever.jac_site(model, data, int(site)))


def mj_jacBody(m: MjModel, d: MjData, jacp, jacr, body: int) -> None:
    model, data = _pair(m, d)
    point = data.xpos[int(body)].copy()
    _write_jacobians(jacp, jacr, *_lever.jac_point(model, data, int(body), point))


def mj_jac(m: MjModel, d: MjData, jacp, jacr, point, body: int) -> None:
    model, data = _pair(m, d)
    point = _np.asarray(point, dtype=float).reshape(3)
    _write_jacobians(jacp, jacr, *_lever.jac_point(model, data, int(body), point))


def mj_integratePos(m: MjModel, qpos: _np.ndarray, qvel: _np.ndarray, dt: float) -> None:
    """qpos (nq) advanced in place by qvel (nv) for time dt; quaternions turn and stay unit."""
    qpos[...] = _lever.integrate_pos(m._native, _np.asarray(qpos, dtype=float),
                                     _np.asarray(qvel, dtype=float), float(dt))


def mj_differentiatePos(m: MjModel, qvel: _np.ndarray, dt: float, qpos1: _np.ndarray,
                        qpos2: _np.ndarray) -> None:
    """qvel (nv) = the velocity that takes qpos1 to qpos2 in time dt."""
    qvel[...] = _lever.differentiate_pos(m._native, float(dt), _np.asarray(qpos1, dtype=float),
                                         _np.asarray(qpos2, dtype=float))


def mj_setConst(m: MjModel, d: MjData) -> None:
    """Recompute the model's derived constants after editing it (body_mass, dof_armature...)."""
    _pair(m, d)
    _lever.set_const(m._native)


def mj_resetData(m: MjModel, d: MjData) -> None:
    _lever.reset(*_pair(m, d))


def mj_resetDataKeyframe(m: MjModel, d: MjData, key: int) -> None:
    """Reset, then time, qpos, qvel and ctrl from keyframe `key` (an index, as MuJoCo's)."""
    model, data = _pair(m, d)
    if not 0 <= int(key) < m.nkey:
        raise ValueError(f"keyframe {key} does not exist: this model has {m.nkey} keyframes")
    _lever.reset_keyframe(model, data, int(key))


def mj_name2id(m: MjModel, type, name: str) -> int:
    """The id of a named object, or -1."""
    kind = _OBJ_TYPES.get(int(type))
    if kind is None:
        raise NotImplementedError(f"lever.mujoco: mj_name2id for {mjtObj(int(type)).name}")
    names = getattr(m._native, _OBJECTS[kind][0])
    return names.index(name) if name in names else -1


def mj_id2name(m: MjModel, type, id: int):
    """The name of an object, or None."""
    kind = _OBJ_TYPES.get(int(type))
    if kind is None:
        raise NotImplementedError(f"lever.mujoco: mj_id2name for {mjtObj(int(type)).name}")
    names = getattr(m._native, _OBJECTS[kind][0])
    return names[id] if 0 <= id < len(names) and names[id] else None


def mj_contactForce(m: MjModel, d: MjData, id: int, result: _np.ndarray) -> None:
    """result (6) = contact `id`'s force in its frame: normal, two tangents, torsion, two rolls
    (past its dim zero), decoded from the pyramid's edge forces as MuJoCo's. MuJoCo writes zeros
    for an id outside [0, ncon); lever raises lever.StateError instead."""
    model, data = _pair(m, d)
    result[...] = _lever.contact_force(model, data, int(id)).reshape(_np.shape(result))


def mj_energyPos(m: MjModel, d: MjData) -> None:
    """d.energy[0]: potential energy (gravity and joint springs)."""
    model, data = _pair(m, d)
    kinetic = data.energy[1]
    _lever.compute_energy(model, data)
    data.energy[1] = kinetic


def mj_energyVel(m: MjModel, d: MjData) -> None:
    """d.energy[1]: kinetic energy."""
    model, data = _pair(m, d)
    potential = data.energy[0]
    _lever.compute_energy(model, data)
    data.energy[0] = potential


def __getattr__(name: str):
    if name.startswith(("mj_", "mju_", "mjd_", "mjv_", "mjr_", "mjs_", "Mj", "mjt", "mjOBJ")):
        raise NotImplementedError(f"lever.mujoco: {name} is MuJoCo's but lever does not "
                                  f"implement it")
    raise AttributeError(f"module 'lever.mujoco' has no attribute '{name}'")
