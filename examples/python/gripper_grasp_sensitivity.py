"""The gripper's grasp differentiated: how the box moves when a finger's command changes.

INPUT gripper.xml (lesson 5.3's gripper): from keyframe 'open', the lift's target -0.235 m and
both fingers' 0.045 m held for 300 steps (0.6 s), so that the four finger tips squeeze the box
on the table.
PROCESS lever.derivatives at that state: B = d x' / d ctrl, one step's sensitivity to the
command, and A = d x' / d x, analytic through the contacts with their active set held
(docs/derivatives.md). With a changed target held for 50 steps (0.1 s) and the dynamics
linearised at the grasp, d x_50 / d u = B + A B + ... + A^49 B.
OUTPUT per mm of the left finger's target, the right one's, and both together: the box's
sideways shift, its roll and its sideways velocity after one step and after 0.1 s, and the
fingers' own motion. docs/derivatives.md shows this output (tests/python/test_derivatives.py
holds the page to it).
"""
import numpy as np

import lever
from mjcourse import model_path

SETTLE_STEPS = 300
HORIZON = 50
CTRL = [-0.235, 0.045, 0.045]  # lift, left finger, right finger (position servos' targets, m)


def shown(x: float) -> str:
    """Four significant digits; what rounding leaves of a zero (symmetry) as 0."""
    return f"{0.0:>10.1f}" if abs(x) < 1e-9 else f"{x:>10.4g}"


def main():
    model = lever.load(str(model_path("gripper")))
    data = lever.Data(model)
    lever.reset_keyframe(model, data, "open")
    data.ctrl[:] = CTRL
    for _ in range(SETTLE_STEPS):
        lever.step(model, data)
    out = lever.derivatives(model, data)
    A, B = out["A"], out["B"]
    nv = model.nv
    horizon = B.copy()
    for _ in range(HORIZON - 1):
        horizon = A @ horizon + B

    lever.forward(model, data)
    print(f"gripper after {SETTLE_STEPS} steps under ctrl {CTRL}: {data.ncon} contacts, "
          f"{out['nefc']} rows pushing, active set changes within the step: "
          f"{'yes' if out['active_set_changes'] else 'no'}")
    # the columns: left finger, right finger, both (a symmetric squeeze); per mm of target
    columns = np.column_stack([B[:, 1], B[:, 2], B[:, 1] + B[:, 2]])
    later = np.column_stack([horizon[:, 1], horizon[:, 2], horizon[:, 1] + horizon[:, 2]])
    box = 3  # the box's free joint: dofs 3, 4, 5 slide along x, y, z; 6, 7, 8 turn about its axes
    rows = [  # (what, matrix, row of x = [dq; qvel], unit per mm of target)
        ("left finger closes, one step (mm)", columns, 1, 1.0),
        ("right finger closes, one step (mm)", columns, 2, 1.0),
        ("box y, one step (mm)", columns, box + 1, 1.0),
        ("box roll about x, one step (mrad)", columns, box + 3, 1.0),
        ("box y velocity, one step (mm/s)", columns, nv + box + 1, 1.0),
        ("box y after 0.1 s (mm)", later, box + 1, 1.0),
        ("box y velocity after 0.1 s (mm/s)", later, nv + box + 1, 1.0),
    ]
    print(f"{'per mm of finger target':36s}{'left':>10s}{'right':>10s}{'both':>10s}")
    for what, matrix, row, unit in rows:
        print(f"{what:36s}" + "".join(shown(unit * x) for x in matrix[row]))


if __name__ == "__main__":
    main()
