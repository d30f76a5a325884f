"""Lesson 5.2: a 7-DOF arm with position servos: which poses are singular, and why the model needs
armature to be stable at all.

INPUT panda7.xml (7-DOF Panda-class arm, <general> position servos, implicit integrator, keyframe
`home`)
PROCESS as examples/l5_2_seven_dof.cpp, line for line (a packaging test compares the two):
(1) reset to the `home` keyframe (mj_resetDataKeyframe) and print the state it gives;
(2) the ee site's 6 x 7 Jacobian at home (mj_jacSite): singular values, manipulability
sqrt(det(J J^T)), condition number; then `lever check`'s section (7): the most singular poses
over the joint ranges and which joint axes align there;
(3) the step's linearisation at home by central differences of mj_step: spectral radius under
the model's implicit integrator and under explicit Euler; then section (8): the largest stable
timesteps and the smallest armature that keeps Euler stable, confirmed by simulation
OUTPUT printed tables

Run: python examples/python/l5_2_seven_dof.py
"""
import lever
import lever.mujoco as mujoco
import numpy as np

from mjcourse import model_path


def as_list(values, spec: str = "%.4g") -> str:
    """[a b c], each as C's printf writes it (the C++ program's format), -0 written as 0."""
    return "[" + " ".join(spec % (float(x) + 0.0) for x in values) + "]"


def number(x) -> float:
    """A figure of lever.check's report: JSON writes infinity as null."""
    return float("inf") if x is None else float(x)


def step_radius(model: mujoco.MjModel, qpos, qvel, ctrl, eps: float = 1e-6) -> float:
    """Spectral radius of d[qpos'; qvel'] / d[qpos; qvel], central differences of mj_step."""
    data = mujoco.MjData(model)
    n = model.nq + model.nv
    A = np.zeros((n, n))
    for i in range(n):
        out = []
        for sign in (1.0, -1.0):
            mujoco.mj_resetData(model, data)
            data.qpos[:], data.qvel[:], data.ctrl[:] = qpos, qvel, ctrl
            if i < model.nq:
                data.qpos[i] += sign * eps
            else:
                data.qvel[i - model.nq] += sign * eps
            mujoco.mj_step(model, data)
            out.append(np.concatenate([data.qpos, data.qvel]))
        A[:, i] = (out[0] - out[1]) / (2 * eps)
    return float(np.max(np.abs(np.linalg.eigvals(A))))


def main() -> None:
    path = str(model_path("panda7"))
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    # lever check's sections (7) and (8) at the keyframe, as `lever check --key home` runs them
    report = lever.check(lever.load(path), key="home")
    st = report["step_stability"]

    # (1) the keyframe
    mujoco.mj_resetDataKeyframe(model, data, 0)  # keyframe 0, `home`
    print(f"(1) {report['model']}: {model.njnt} joints, integrator {st['integrator']}, "
          f"timestep {model.opt.timestep:g} s; keyframe home:")
    print(f"    qpos {as_list(data.qpos)}")
    print(f"    ctrl {as_list(data.ctrl)} (position targets)")
    qpos, qvel, ctrl = data.qpos.copy(), data.qvel.copy(), data.ctrl.copy()

    # (2) the Jacobian at home
    mujoco.mj_forward(model, data)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jacp, jacr, model.site("ee").id)
    J = np.vstack([jacp, jacr])
    sigma = np.linalg.svd(J, compute_uv=False)
    print(f"(2) ee Jacobian (6 x {model.nv}) at home: singular values {as_list(sigma)}")
    print(f"    manipulability sqrt(det(J J^T)) = {np.sqrt(np.linalg.det(J @ J.T)):.4g}, "
          f"condition number = {sigma[0] / sigma[-1]:.4g}")
    for site in report["singular_poses"]["sites"]:
        for at in site["worst"]:
            print(f"    {at['where']}: q = {as_list(at['qpos'], '%.3f')} "
                  f"sigma_min {at['sigma'][-1]:.3g}, condition {number(at['condition']):.3g}")
            for a in at["aligned"]:
                print(f"      {a['joints'][0]} and {a['joints'][1]} "
                      f"{'collinear' if a['collinear'] else 'parallel'}")

    # (3) stability of the step at home
    euler_model = mujoco.MjModel.from_xml_path(path)
    euler_model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    print(f"(3) spectral radius of the step at home: {st['integrator']} "
          f"{step_radius(model, qpos, qvel, ctrl):.4f}, "
          f"Euler {step_radius(euler_model, qpos, qvel, ctrl):.4f} (stable below 1)")
    home = st["states"][0]
    print(f"    largest stable timestep: {st['integrator']} "
          f"{number(home['max_timestep_model']):.4g} s, "
          f"Euler {number(home['max_timestep_euler']):.4g} s")
    print(f"    smallest armature for a stable Euler step at {st['timestep']:g} s: "
          f"{number(home['armature_all']):.4g} kg m^2 on every joint")
    for joint, need in zip(st["joints"], home["armature_each"]):
        print(f"      {joint}: {number(need):.4g} with the others given {st['ample']:g} x that")
    for run in home["runs"]:
        outcome = "settles" if run["settled"] else "does not settle"
        if not run["bounded"]:
            outcome = f"blows up at step {run['blowup_step']}"
        print(f"    simulated {run['steps']} steps, {run['integrator']} with armature "
              f"{run['armature']}: {outcome} (|qvel| {run['final_qvel']:.3g} over the last tenth)")


if __name__ == "__main__":
    main()
