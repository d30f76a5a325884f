"""Lesson 5.1's lab, run headless: "A torque budget for a two-link arm".

What the lab page does, in Python: press "Bent pose" (qpos = [0.6, -1.2], qvel = 0), switch
gravity compensation on, and before every step run the lab's controller
    data.ctrl[0] = t1 + gc * data.qfrc_bias[0]; data.ctrl[1] = t2 + gc * data.qfrc_bias[1]
on whatever data holds, then mj_step; print the lab's five readouts with their digits every 0.5 s.
With t1 = t2 = 0 the arm floats: gravity compensation holds it where it was put.

Run: python3 examples/python/l5_1_lab.py [t1 t2 gc seconds]
"""
import sys

import lever.mujoco as mujoco
from mjcourse import model_path

READOUTS = [  # (label, expression, digits), as the lab's spec gives them
    ("qfrc_bias, shoulder (N m)", lambda d: d.qfrc_bias[0], 3),
    ("qfrc_bias, elbow (N m)", lambda d: d.qfrc_bias[1], 3),
    ("applied, shoulder (N m)", lambda d: d.actuator_force[0], 2),
    ("applied, elbow (N m)", lambda d: d.actuator_force[1], 2),
    ("limit force, shoulder (N m)", lambda d: d.qfrc_constraint[0], 3),
]


def main(t1: float = 0.0, t2: float = 0.0, gc: float = 1.0, seconds: float = 2.0) -> None:
    model = mujoco.MjModel.from_xml_path(str(model_path("arm2")))
    data = mujoco.MjData(model)
    data.qpos[0] = 0.6  # the "Bent pose" button
    data.qpos[1] = -1.2
    data.qvel.fill(0)
    print(f"  lab: t1 = {t1:g} N m, t2 = {t2:g} N m, gravity compensation "
          f"{'on' if gc else 'off'}, from the bent pose")
    steps = round(seconds / model.opt.timestep)
    every = round(0.5 / model.opt.timestep)
    for k in range(steps + 1):
        if k % every == 0:
            values = ", ".join(f"{label} {expr(data):.{digits}f}" for label, expr, digits in READOUTS)
            print(f"  t = {data.time:4.2f} s: qpos = [{data.qpos[0]:.4f} {data.qpos[1]:.4f}] rad; "
                  f"{values}")
        if k == steps:
            break
        data.ctrl[0] = t1 + gc * data.qfrc_bias[0]  # the lab's controller
        data.ctrl[1] = t2 + gc * data.qfrc_bias[1]
        mujoco.mj_step(model, data)


if __name__ == "__main__":
    main(*[float(a) for a in sys.argv[1:5]])
