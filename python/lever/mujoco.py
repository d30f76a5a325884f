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

import copy as _copy
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
    "mjd_transitionFD",
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


class mjtStage(_enum.IntEnum):
    """Pipeline stages (mjtStage): what a user sensor's callback is called after."""
    mjSTAGE_NONE = 0
    mjSTAGE_POS = 1
    mjSTAGE_VEL = 2
    mjSTAGE_ACC = 3


class mjtDisableBit(_enum.IntFlag):
    """Bits of model.opt.disableflags (mjtDisableBit): <option><flag name="disable">."""
    mjDSBL_CONSTRAINT = 1 << 0
    mjDSBL_EQUALITY = 1 << 1
    mjDSBL_FRICTIONLOSS = 1 << 2
    mjDSBL_LIMIT = 1 << 3
    mjDSBL_CONTACT = 1 << 4
    mjDSBL_PASSIVE = 1 << 5
    mjDSBL_GRAVITY = 1 << 6
    mjDSBL_CLAMPCTRL = 1 << 7
    mjDSBL_WARMSTART = 1 << 8
    mjDSBL_FILTERPARENT = 1 << 9
    mjDSBL_ACTUATION = 1 << 10
    mjDSBL_REFSAFE = 1 << 11
    mjDSBL_SENSOR = 1 << 12


class mjtEnableBit(_enum.IntFlag):
    """Bits of model.opt.enableflags (mjtEnableBit): <option><flag name="enable">."""
    mjENBL_OVERRIDE = 1 << 0
    mjENBL_ENERGY = 1 << 1
    mjENBL_FWDINV = 1 << 2
    mjENBL_SENSORNOISE = 1 << 3
    mjENBL_MULTICCD = 1 << 4


# lever's arrays that MuJoCo has under the same name, shape and meaning (the field table)
_MODEL_FIELDS = frozenset(f["name"] for f in _lever.model_field_table() if f["mujoco"])
_DATA_FIELDS = frozenset(f["name"] for f in _lever.data_field_table() if f["mujoco"])
_SIZES = ("nq", "nv", "nu", "nbody", "njnt", "ngeom", "nsite", "npair", "nexclude", "nsensor",
          "nsensordata", "neq", "nmocap", "nmesh", "nmeshvert", "nmeshgraph", "nmeshface",
          "nconmax",
          "njmax", "ntendon", "nwrap", "nuser_body", "nuser_jnt", "nuser_geom", "nuser_site",
          "nuser_tendon", "nuser_actuator", "nuser_sensor", "na")
# keyframe arrays lever has, as MuJoCo's (nkey rows)
_KEY_FIELDS = ("key_time", "key_qpos", "key_qvel", "key_ctrl", "key_mpos", "key_mquat")
# the mjModel arrays model.body(...) and the other accessors reach
_MODEL_OFFERED = _MODEL_FIELDS | {"dof_Madr"}


# What lever.mujoco covers, generated from the field table, for the errors below
_COVERED = {
    "MODEL": ", ".join(sorted(_MODEL_FIELDS | set(_SIZES) | set(_KEY_FIELDS) |
                              {"dof_Madr", "nM"})),
    "DATA": ", ".join(sorted(_DATA_FIELDS | {"time", "ncon", "nefc", "ne", "nf", "efc_J",
                                             "contact", "qM"})),
}
_STRUCT = {"MODEL": "mjModel", "DATA": "mjData"}


def _missing(kind: str, name: str):
    """The error for a MuJoCo name lever lacks (NotImplementedError, saying what lever has), or a
    name MuJoCo 2.2.2 lacks too (AttributeError)."""
    if name in getattr(_mujoco_names, kind):
        return NotImplementedError(
            f"lever.mujoco: {_STRUCT[kind]}.{name} is MuJoCo's but lever does not compute it; "
            f"lever.mujoco's {_STRUCT[kind]} has (lever's field table): {_COVERED[kind]}")
    return AttributeError(f"'Mj{_STRUCT[kind][2:]}' object has no attribute '{name}'")


# ---- named access: model.joint('elbow').axis, data.site('ee').xpos -------------------------------

# object type -> (name list in lever's Model, size attribute)
_OBJECTS = {
    "body": ("body_name", "nbody"),
    "joint": ("jnt_name", "njnt"),
    "geom": ("geom_name", "ngeom"),
    "site": ("site_name", "nsite"),
    "actuator": ("actuator_name", "nu"),
    "sensor": ("sensor_name", "nsensor"),
}
_OBJ_TYPES = {
    mjtObj.mjOBJ_BODY: "body", mjtObj.mjOBJ_XBODY: "body", mjtObj.mjOBJ_JOINT: "joint",
    mjtObj.mjOBJ_GEOM: "geom", mjtObj.mjOBJ_SITE: "site", mjtObj.mjOBJ_ACTUATOR: "actuator",
    mjtObj.mjOBJ_SENSOR: "sensor",
}

# MuJoCo's accessors show an object's rows of every array its count sizes, under the array's name
# less the object's prefix (model.body(i).mass is body_mass[i], data.geom(i).xpos geom_xpos[i]);
# a joint's rows of the nq- and nv-sized arrays are its coordinates and dofs. kind -> [(the size
# counting the rows, the prefix)], for mjModel and for mjData.
_MODEL_ROWS = {
    "body": [("nbody", "body_")],
    "joint": [("njnt", "jnt_"), ("nv", "dof_"), ("nq", "")],
    "geom": [("ngeom", "geom_")],
    "site": [("nsite", "site_")],
    "actuator": [("nu", "actuator_")],
    "sensor": [("nsensor", "sensor_")],
}
_DATA_ROWS = {
    "body": [("nbody", "")],
    "joint": [("njnt", ""), ("nv", ""), ("nq", "")],
    "geom": [("ngeom", "geom_")],
    "site": [("nsite", "site_")],
    "actuator": [("nu", "actuator_"), ("na", "")],
    "sensor": [("nsensordata", "sensor")],  # data.sensor(i).data: its numbers in sensordata
}


def _accessor_table(mujoco_arrays: dict, rows_of_kind: dict) -> dict:
    """kind -> {attribute: (MuJoCo's array, the size counting its rows)} from MuJoCo's table."""
    table = {}
    for kind, sources in rows_of_kind.items():
        attributes = {}
        for array, rows in mujoco_arrays.items():
            for size, prefix in sources:
                if rows == size and array.startswith(prefix):
                    attributes.setdefault(array[len(prefix):], (array, rows))
        # where a joint's array and its dofs' share a name, MuJoCo's joint view shows the dofs'
        # (bodyid), except the limit's solref and solimp, which are the joint's
        if kind == "joint":
            for name in ("solref", "solimp"):
                if "jnt_" + name in mujoco_arrays:
                    attributes[name] = ("jnt_" + name, mujoco_arrays["jnt_" + name])
        table[kind] = attributes
    return table


_MODEL_ACCESS = _accessor_table(_mujoco_names.MODEL, _MODEL_ROWS)
_DATA_ACCESS = _accessor_table(_mujoco_names.DATA, _DATA_ROWS)


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
    names_attr, size_attr = _OBJECTS[kind]
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


def _object_rows(owner, native_model, access: dict, offered, kind: str, index: int, attr: str,
                 struct: str) -> _np.ndarray:
    """The object's rows of the array behind `attr`: a view of lever's array when lever has it
    (`offered`), NotImplementedError when only MuJoCo does, AttributeError when neither."""
    source = access[kind].get(attr)
    if source is None:
        raise AttributeError(f"a {struct} {kind} has no attribute '{attr}'")
    array_name, rows = source
    if array_name not in offered:
        raise NotImplementedError(
            f"lever.mujoco: {struct}.{kind}(...).{attr} ({struct}.{array_name}) is MuJoCo's but "
            f"lever does not compute it; a {kind} has here: "
            f"{', '.join(sorted(a for a, (n, _) in access[kind].items() if n in offered))}")
    array = getattr(owner, array_name)
    if rows in ("nq", "nv"):  # a joint's coordinates or dofs
        return _joint_slice(array, native_model, index, rows == "nq")
    if rows == "nsensordata":  # a sensor's numbers
        adr, dim = int(native_model.sensor_adr[index]), int(native_model.sensor_dim[index])
        return array[adr:adr + dim]
    return _row(array, index)


class _ModelObject:
    """model.body(...), model.joint(...), ...: the object's rows of the model arrays."""

    def __init__(self, model: "MjModel", kind: str, key):
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_kind", kind)
        object.__setattr__(self, "id", _resolve(model._native, kind, key))
        names = getattr(model._native, _OBJECTS[kind][0])
        object.__setattr__(self, "name", names[self.id])

    def _array(self, attr: str) -> _np.ndarray:
        model = self._model
        return _object_rows(model, model._native, _MODEL_ACCESS, _MODEL_OFFERED, self._kind,
                            self.id, attr, "model")

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
        data = self._data
        return _object_rows(data, data._model._native, _DATA_ACCESS, _DATA_FIELDS, self._kind,
                            self.id, attr, "data")

    def __getattr__(self, attr: str):
        return self._array(attr)

    def __setattr__(self, attr: str, value) -> None:
        self._array(attr)[...] = value

    def __repr__(self) -> str:
        return f"<data {self._kind} {self.id} '{self.name}'>"


# ---- MjModel, MjOption, MjData -------------------------------------------------------------------

class MjOption:
    """model.opt: timestep, gravity, integrator, the solver (solver, iterations, tolerance), the
    flags (disableflags, enableflags: MuJoCo's mjtDisableBit and mjtEnableBit bits) and the
    contact override (o_margin, o_solref, o_solimp), written through to lever's model."""

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

    @property
    def solver(self) -> int:
        return self._native.solver

    @solver.setter
    def solver(self, value: int) -> None:
        self._native.solver = int(value)  # mjtSolver: 0 PGS, 1 CG or 2 Newton

    @property
    def iterations(self) -> int:
        return self._native.iterations

    @iterations.setter
    def iterations(self, value: int) -> None:
        self._native.iterations = int(value)

    @property
    def tolerance(self) -> float:
        return self._native.tolerance

    @tolerance.setter
    def tolerance(self, value: float) -> None:
        self._native.tolerance = float(value)

    @property
    def disableflags(self) -> int:
        return self._native.disableflags

    @disableflags.setter
    def disableflags(self, value: int) -> None:
        self._native.disableflags = int(value)

    @property
    def enableflags(self) -> int:
        return self._native.enableflags

    @enableflags.setter
    def enableflags(self, value: int) -> None:
        self._native.enableflags = int(value)

    @property
    def o_margin(self) -> float:
        return self._native.o_margin

    @o_margin.setter
    def o_margin(self, value: float) -> None:
        self._native.o_margin = float(value)

    @property
    def o_solref(self) -> _np.ndarray:
        return self._native.o_solref

    @o_solref.setter
    def o_solref(self, value) -> None:
        self._native.o_solref[:] = value

    @property
    def o_solimp(self) -> _np.ndarray:
        return self._native.o_solimp

    @o_solimp.setter
    def o_solimp(self, value) -> None:
        self._native.o_solimp[:] = value

    def __getattr__(self, name: str):
        if name in _mujoco_names.OPTION:
            raise NotImplementedError(f"lever.mujoco: mjOption.{name} is MuJoCo's but lever "
                                      f"does not use it")
        raise AttributeError(f"'MjOption' object has no attribute '{name}'")

    def __setattr__(self, name: str, value) -> None:
        if name in ("timestep", "gravity", "integrator", "solver", "iterations", "tolerance",
                    "disableflags", "enableflags", "o_margin", "o_solref", "o_solimp"):
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
    def nM(self) -> int:
        """Entries of MuJoCo's sparse M (data.qM)."""
        return len(_sparse_rows(self._native)[1])

    @property
    def dof_Madr(self) -> _np.ndarray:
        """(nv,) where each dof's row starts in data.qM (computed from dof_parentid: read-only)."""
        out = _sparse_rows(self._native)[0]
        out.flags.writeable = False
        return out

    @property
    def nkey(self) -> int:
        return self._native.nkey

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

    # pickle and copies: the lever.Model beneath (every array of the field table, the names,
    # the keyframes and the options), as MuJoCo's MjModel pickles and copies whole
    def __reduce__(self):
        return (MjModel, (self._native,))

    def __copy__(self) -> "MjModel":
        return MjModel(_lever.copy_model(self._native))

    def __deepcopy__(self, memo) -> "MjModel":
        return MjModel(_lever.copy_model(self._native))

    def __repr__(self) -> str:
        return f"<lever.mujoco.MjModel {self._native.name!r} nq={self.nq} nu={self.nu}>"


# ---- contacts: d.contact as MuJoCo's bindings show it -------------------------------

_CONTACT_MEMBERS = frozenset(_lever.contact_members()) | {"geom"}


def _contact_member(native, name: str, rows) -> _np.ndarray:
    """Member `name` of the contacts `rows` (a slice or an index array of range(ncon)): a view of
    lever's memory for a slice; `geom` is MuJoCo's (n, 2) pair [geom1, geom2]."""
    if name == "geom":
        return _np.stack([_contact_member(native, "geom1", rows),
                          _contact_member(native, "geom2", rows)], axis=-1)
    if name not in _CONTACT_MEMBERS:
        if name in _mujoco_names.CONTACT:
            raise NotImplementedError(
                f"lever.mujoco: MjContact.{name} is MuJoCo's but lever does not compute it; a "
                f"contact has here: {', '.join(sorted(_CONTACT_MEMBERS))}")
        raise AttributeError(f"'MjContact' object has no attribute '{name}'")
    return native.contact_field(name)[rows]


class _MjContact:
    """One contact (MuJoCo's MjContact): pos (3,), frame (9,: normal, then two tangents), dist,
    geom1, geom2, geom (2,), dim, friction (5,), solref (2,), solimp (5,), includemargin,
    exclude, efc_address, mu. Arrays are views of lever's memory; numbers are read when asked
    for."""

    def __init__(self, native, index: int):
        object.__setattr__(self, "_native", native)
        object.__setattr__(self, "_index", index)

    def __getattr__(self, name: str):
        value = _contact_member(self._native, name, self._index)
        return value if _np.ndim(value) else value.item()

    def __setattr__(self, name: str, value) -> None:
        raise AttributeError(f"lever.mujoco: MjContact.{name} is computed by mj_forward; it "
                             f"cannot be set")

    def __repr__(self) -> str:
        return (f"<MjContact geom1={self.geom1} geom2={self.geom2} dist={self.dist:g} "
                f"dim={self.dim}>")


def _as_slice(indices: range) -> slice:
    """The slice of an array that picks `indices` (a range within the array's length)."""
    if not len(indices):
        return slice(0, 0)
    stop = indices.stop if indices.stop >= 0 else None  # a reversed range running down to 0
    return slice(indices.start, stop, indices.step)


class _MjContactList:
    """d.contact: len() is ncon; d.contact[i] is one contact; d.contact[a:b] the contacts a to b
    (Python's slice of range(ncon)); d.contact.dist and the other members are arrays over those
    contacts (views: shape (n,) or (n, k)), as MuJoCo's."""

    def __init__(self, native, rows=slice(None)):
        object.__setattr__(self, "_native", native)
        object.__setattr__(self, "_rows", rows)

    def _indices(self) -> range:
        return range(self._native.ncon)[self._rows]

    def __len__(self) -> int:
        return len(self._indices())

    def __getitem__(self, index):
        indices = self._indices()
        if isinstance(index, slice):
            return _MjContactList(self._native, _as_slice(indices[index]))
        try:
            return _MjContact(self._native, indices[int(index)])
        except IndexError:
            raise IndexError(f"contact index {index} out of range: {len(indices)} contacts "
                             f"(ncon is {self._native.ncon})") from None

    def __iter__(self):
        return (_MjContact(self._native, i) for i in self._indices())

    def __getattr__(self, name: str) -> _np.ndarray:
        return _contact_member(self._native, name, _as_slice(self._indices()))

    def __repr__(self) -> str:
        return f"<MjContactList of {len(self)} contacts>"


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
        return self._native.ne

    @property
    def solver_iter(self) -> int:
        """The constraint solver's iterations (MuJoCo 2.2.2's d->solver_iter; MuJoCo 3's
        d.solver_niter[0] for one island): CG's iterations and PGS's sweeps as MuJoCo counts them;
        with Newton, lever's own Newton steps."""
        return self._native.solver_iter

    @property
    def nf(self) -> int:
        return self._native.nf

    @property
    def ncon(self) -> int:
        return self._native.ncon

    @property
    def qM(self) -> _np.ndarray:
        """(nM,) M(q) in MuJoCo's sparse layout (model.dof_Madr), read from lever's dense M
        (data.M) when asked: a read-only copy, for mj_fullM(model, dst, data.qM)."""
        _, columns = _sparse_rows(self._model._native)
        rows = _np.repeat(_np.arange(self._model.nv),
                          _np.diff(_np.append(self._model.dof_Madr, len(columns))))
        out = self._native.M[rows, columns]
        out.flags.writeable = False
        return out

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

    # pickle and copies: the lever.Data beneath (every array of the field table, the contacts,
    # efc_J and the warnings) with its model. A copy keeps its MjModel, as MuJoCo's MjData (which
    # holds no model) is used with the model it is given.
    def __reduce__(self):
        return (_data_from_native, (self._model, self._native))

    def __copy__(self) -> "MjData":
        return _data_from_native(self._model, _copy.copy(self._native))

    def __deepcopy__(self, memo) -> "MjData":
        return _data_from_native(self._model, _copy.copy(self._native))

    def __repr__(self) -> str:
        return f"<lever.mujoco.MjData time={self.time:g} nefc={self.nefc}>"


def _data_from_native(model: MjModel, native) -> MjData:
    """An MjData around a lever.Data (an unpickled or copied one), paired with `model`."""
    data = MjData.__new__(MjData)
    object.__setattr__(data, "_model", model)
    object.__setattr__(data, "_native", native)
    native._adopt_model(model._native)
    return data


def _add_named_access(cls, view) -> None:
    """cls.body(key), cls.joint(key) (also cls.jnt), ...: `view(self, kind, key)` for each kind of
    object, as MuJoCo's bindings name its accessors."""
    for kind in ("body", "joint", "geom", "site", "actuator", "sensor"):
        setattr(cls, kind, lambda self, key, kind=kind: view(self, kind, key))
    cls.jnt = cls.joint


_add_named_access(MjModel, _ModelObject)
_add_named_access(MjData, _DataObject)


# ---- functions -----------------------------------------------------------------------------------

# mujoco.set_mjcb_sensor's callback, or None
_mjcb_sensor = None


def set_mjcb_sensor(callback) -> None:
    """MuJoCo's sensor callback: callback(m, d, stage) writes the user sensors' numbers into
    d.sensordata after each stage that has user sensors (None: they stay as they are)."""
    global _mjcb_sensor
    _mjcb_sensor = callback


def get_mjcb_sensor():
    return _mjcb_sensor


# mujoco.set_mjcb_act_gain's, set_mjcb_act_bias's and set_mjcb_act_dyn's callbacks, or None: as
# MuJoCo's globals, they serve every model's actuators whose gaintype, biastype or dyntype is user
_mjcb_act_gain = None
_mjcb_act_bias = None
_mjcb_act_dyn = None


def set_mjcb_act_gain(callback) -> None:
    """MuJoCo's user gain: callback(m, d, id) -> float, the gain of actuator id for every model's
    actuators with gaintype user (None: MuJoCo's value without a callback, gain 1)."""
    global _mjcb_act_gain
    _mjcb_act_gain = callback


def get_mjcb_act_gain():
    return _mjcb_act_gain


def set_mjcb_act_bias(callback) -> None:
    """MuJoCo's user bias: callback(m, d, id) -> float, the bias of actuator id for every model's
    actuators with biastype user (None: bias 0)."""
    global _mjcb_act_bias
    _mjcb_act_bias = callback


def get_mjcb_act_bias():
    return _mjcb_act_bias


def set_mjcb_act_dyn(callback) -> None:
    """MuJoCo's user activation dynamics: callback(m, d, id) -> float, act_dot of actuator id for
    every model's actuators with dyntype user (None: act_dot 0)."""
    global _mjcb_act_dyn
    _mjcb_act_dyn = callback


def get_mjcb_act_dyn():
    return _mjcb_act_dyn


def _for_pair(callback, m, d):
    """A module-level callback as the native model calls it, handed this call's MjModel and MjData
    (None stays None)."""
    if callback is None:
        return None
    return lambda _model, _data, arg: callback(m, d, arg)


def _pair(m: MjModel, d: MjData):
    if not isinstance(m, MjModel) or not isinstance(d, MjData):
        raise TypeError("expected (MjModel, MjData)")
    if d._model is not m:
        # MuJoCo's functions use the model they are given: an MjData of another model of the same
        # sizes (a copy, an unpickled one) is paired with this one; other sizes are refused
        d._native._adopt_model(m._native)
        object.__setattr__(d, "_model", m)
    # the callbacks see this call's MjModel and MjData (installed when any of them changed)
    installed = (_mjcb_sensor, _mjcb_act_gain, _mjcb_act_bias, _mjcb_act_dyn, id(d))
    if m.__dict__.get("_mjcb_installed") != installed:
        m._native.set_sensor_callback(_for_pair(_mjcb_sensor, m, d))
        m._native.set_actuator_callbacks(gain=_for_pair(_mjcb_act_gain, m, d),
                                         bias=_for_pair(_mjcb_act_bias, m, d),
                                         dyn=_for_pair(_mjcb_act_dyn, m, d))
        object.__setattr__(m, "_mjcb_installed", installed)
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


def _sparse_rows(native):
    """MuJoCo's sparse layout of M (qM): dof i's row holds M[i, j] for j = i, then each dof on
    the path to the world (dof_parentid), from address dof_Madr[i]. Returns (dof_Madr, the
    column j of each entry of qM)."""
    parent = native.dof_parentid
    madr, columns = [], []
    for i in range(native.nv):
        madr.append(len(columns))
        j = i
        while j >= 0:
            columns.append(j)
            j = int(parent[j])
    return _np.array(madr, dtype=_np.int32), _np.array(columns, dtype=_np.int64)


def mj_fullM(m: MjModel, *args) -> None:
    """dst = M(q) as a dense nv x nv matrix: mj_fullM(model, dst, data.qM) (MuJoCo up to 3.9) or
    mj_fullM(model, data, dst) (MuJoCo 3.10+)."""
    if len(args) == 2 and isinstance(args[0], MjData):
        d, dst = args
        _pair(m, d)
        dst[...] = d._native.M.reshape(_np.shape(dst))
        return
    dst, qM = args
    madr, columns = _sparse_rows(m._native)
    qM = _np.asarray(qM, dtype=float)
    full = _np.zeros((m.nv, m.nv))
    rows = _np.repeat(_np.arange(m.nv), _np.diff(_np.append(madr, len(columns))))
    full[rows, columns] = qM
    full[columns, rows] = qM
    dst[...] = full.reshape(_np.shape(dst))


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


def _output(array, rows: int, cols: int, name: str):
    """A writable, C-contiguous float64 (rows x cols) array the caller passed, or None."""
    if array is None:
        return None
    if (not isinstance(array, _np.ndarray) or array.dtype != _np.float64 or
            not array.flags.c_contiguous or not array.flags.writeable):
        raise TypeError(f"mjd_transitionFD: {name} must be a writable, C-contiguous float64 "
                        f"numpy array")
    if array.size != rows * cols or (array.ndim == 2 and array.shape != (rows, cols)):
        raise ValueError(f"mjd_transitionFD: {name} must be {rows} x {cols}, got "
                         f"{array.shape}")
    return array.reshape(rows, cols)


def mjd_transitionFD(m: MjModel, d: MjData, eps: float, flg_centered: int, A, B, C, D) -> None:
    """The step's transition matrices at d's state, d x' = A dx + B du, with MuJoCo's signature
    and layout (x = [dq; qvel; act], dq qpos's tangent as mj_differentiatePos gives it; A
    (2nv + na x 2nv + na) and B (2nv + na x nu) written row-major in place, None skips one).

    Computed analytically, not by finite differences: lever.derivatives, exact through the
    integrator (Euler, RK4, implicit), the actuators, joint limits and contacts with their
    active set held (docs/derivatives.md). So ``eps`` and ``flg_centered`` are accepted for
    MuJoCo's signature and not used. Where the active set changes within the step (the step is not
    differentiable there) A and B are the start's piece and a RuntimeWarning says so.

    C and D, the sensors' derivatives, lever does not compute: a model with sensors must pass None
    for them (NotImplementedError otherwise); without sensors they are empty and left so.
    """
    model, data = _pair(m, d)
    nv, nu, na, nsensordata = m.nv, m.nu, m.na, m.nsensordata
    A = _output(A, 2 * nv + na, 2 * nv + na, "A")
    B = _output(B, 2 * nv + na, nu, "B")
    C = _output(C, nsensordata, 2 * nv + na, "C")
    D = _output(D, nsensordata, nu, "D")
    if nsensordata > 0 and (C is not None or D is not None):
        raise NotImplementedError("lever.mujoco: mjd_transitionFD's C and D (the sensors' "
                                  "derivatives) are MuJoCo's but lever does not compute them; "
                                  "pass None for C and D")
    del eps, flg_centered  # analytic: no difference is taken
    if A is None and B is None:
        return
    from . import derivatives as _derivatives
    out = _derivatives(model, data)
    if A is not None:
        A[...] = out["A"]
    if B is not None:
        B[...] = out["B"]


def __getattr__(name: str):
    if name.startswith(("mj_", "mju_", "mjd_", "mjv_", "mjr_", "mjs_", "Mj", "mjt", "mjOBJ")):
        raise NotImplementedError(f"lever.mujoco: {name} is MuJoCo's but lever does not "
                                  f"implement it")
    raise AttributeError(f"module 'lever.mujoco' has no attribute '{name}'")
