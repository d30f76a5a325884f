"""Lesson 5.1, exercise 2: where can a weaker arm hold its tip still?

INPUT   arm2.xml, with the shoulder motor limited to 6 N m (less than the 7.946 N m the straight
        arm weighs at the horizontal); the elbow keeps its 15 N m
PROCESS (1) sample the joint ranges densely; at each pose, at rest, the motors must supply
            qfrc_bias (the gravity torque): the pose is holdable when every motor can;
        (2) map the tip positions (x, z) relative to the shoulder on a 2 cm grid;
        (3) find the farthest horizontal distance from the shoulder among holdable poses, and
            refine it on a finer grid around the best sample
OUTPUT  the holdable share of the poses, the farthest reach and its pose, a text map

Why: at rest tau_g1 = g (m1 + m2) x_com, the arm's weight times the horizontal distance of its
centre of mass from the shoulder, so 6 N m allows |x_com| <= 0.34 m; the farthest holdable reach
keeps link 2 level and link 1 as low as the budget allows (see the C++ version for the whole map).

Run: python3 examples/python/l5_1_exercise2_workspace.py   (written against MuJoCo's Python API;
lever runs it through `import lever.mujoco as mujoco`)
"""
import numpy as np

import lever.mujoco as mujoco
from mjcourse import model_path

SHOULDER_LIMIT = 6.0  # N m


def holdable_tips(model, data, q1s, q2s):
    """(x, z, q1, q2) of every holdable pose on the grid, tip relative to the shoulder."""
    limit = np.abs(model.actuator_ctrlrange).max(axis=1)
    shoulder = None
    found = []
    for q1 in q1s:
        for q2 in q2s:
            data.qpos[:] = [q1, q2]
            data.qvel[:] = 0
            mujoco.mj_forward(model, data)
            if shoulder is None:
                shoulder = data.joint("shoulder").xanchor.copy()
            if np.all(np.abs(data.qfrc_bias) <= limit):
                tip = data.site("ee").xpos - shoulder
                found.append((tip[0], tip[2], q1, q2))
    return np.array(found)


def main() -> None:
    model = mujoco.MjModel.from_xml_path(str(model_path("arm2")))
    model.actuator_ctrlrange[0] = [-SHOULDER_LIMIT, SHOULDER_LIMIT]
    data = mujoco.MjData(model)
    (lo1, hi1), (lo2, hi2) = model.jnt_range
    coarse = holdable_tips(model, data, np.linspace(lo1, hi1, 181), np.linspace(lo2, hi2, 261))
    print(f"  shoulder motor limited to {SHOULDER_LIMIT:g} N m: "
          f"holdable: {100.0 * len(coarse) / (181 * 261):.1f}% of the sampled poses")
    best = coarse[np.argmax(np.abs(coarse[:, 0]))]
    step1, step2 = (hi1 - lo1) / 180, (hi2 - lo2) / 260
    fine = holdable_tips(model, data,
                         np.clip(np.linspace(best[2] - step1, best[2] + step1, 201), lo1, hi1),
                         np.clip(np.linspace(best[3] - step2, best[3] + step2, 201), lo2, hi2))
    best = fine[np.argmax(np.abs(fine[:, 0]))]
    print(f"  farthest horizontal distance from the shoulder among holdable poses: "
          f"{abs(best[0]):.3f} m at q = [{best[2]:.3f} {best[3]:.3f}] rad (tip z {best[1]:+.3f} m)")
    cells = {(int(np.floor(x / 0.02)), int(np.floor(z / 0.02))) for x, z, _, _ in coarse}
    print("  holdable tips, 2 cm cells every 4 cm (x right, z up, + the shoulder):")
    for zc in range(22, -24, -2):
        row = "".join("+" if (xc, zc) == (0, 0) else ("#" if (xc, zc) in cells else ".")
                      for xc in range(-46, 47, 2))
        print("    " + row)


if __name__ == "__main__":
    main()
