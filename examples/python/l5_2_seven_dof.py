"""Lesson 5.2: a 7-DOF arm with position servos: which poses are singular, and why the model needs
armature to be stable at all.

INPUT panda7.xml (7-DOF Panda-class arm, <general> position servos, implicit integrator, keyframe
`home`)
PROCESS (1) reset to the `home` keyframe (mj_resetDataKeyframe) and print the state it gives;
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
    model = mujoco.MjModel.from_xml_path(str(model_path("panda7")))
    data = mujoco.MjData(model)

    # (1) the keyframe
    mujoco.mj_resetDataKeyframe(model, data, 0)
    print(f"(1) panda7: {model.njnt} joints, timestep {model.opt.timestep:g} s; keyframe home:")
    print(f"    qpos {np.round(data.qpos, 4)}")
    print(f"    ctrl {np.round(data.ctrl, 4)} (position targets)")
    qpos, qvel, ctrl = data.qpos.copy(), data.qvel.copy(), data.ctrl.copy()

    # (2) the Jacobian at home
    mujoco.mj_forward(model, data)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jacp, jacr, model.site("ee").id)
    J = np.vstack([jacp, jacr])
    sigma = np.linalg.svd(J, compute_uv=False)
    print(f"(2) ee Jacobian (6 x {model.nv}) at home: singular values {np.round(sigma, 4)}")
    print(f"    manipulability sqrt(det(J J^T)) = {np.sqrt(np.linalg.det(J @ J.T)):.4g}, "
          f"condition number = {sigma[0] / sigma[-1]:.4g}")
    report = lever.check(lever.load(str(model_path("panda7"))), key="home")
    for site in report["singular_poses"]["sites"]:
        for at in site["worst"]:
            aligned = ", ".join(f"{a['joints'][0]} and {a['joints'][1]} "
                                f"{'collinear' if a['collinear'] else 'parallel'}"
                                for a in at["aligned"])
            print(f"    {at['where']}: q = {np.round(at['qpos'], 3)} sigma_min {at['sigma'][-1]:.3g}"
                  f"; aligned: {aligned or 'none'}")

    # (3) stability of the step at home
    implicit = step_radius(model, qpos, qvel, ctrl)
    euler_model = mujoco.MjModel.from_xml_path(str(model_path("panda7")))
    euler_model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    euler = step_radius(euler_model, qpos, qvel, ctrl)
    print(f"(3) spectral radius of the step at home: implicit {implicit:.4f}, Euler {euler:.4f} "
          f"(stable below 1)")
    st = report["step_stability"]
    home = st["states"][0]
    print(f"    largest stable timestep: implicit {home['max_timestep_model']:.4g} s, "
          f"Euler {home['max_timestep_euler']:.4g} s")
    print(f"    smallest armature for a stable Euler step at {st['timestep']:g} s: "
          f"{home['armature_all']:.4g} kg m^2 on every joint")
    for run in home["runs"]:
        outcome = ("settles" if run["settled"] else
                   f"blows up at step {run['blowup_step']}" if run["blowup_step"] >= 0 else
                   f"does not settle (|qvel| {run['final_qvel']:.3g} at the end)")
        print(f"    simulated, {run['integrator']} with armature {run['armature']}: {outcome}")


if __name__ == "__main__":
    main()
