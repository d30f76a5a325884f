#!/usr/bin/env python3
"""The engine's rooms and the one way their dependencies run.

engine/src holds one folder (room) per pipeline stage, listed below from the lowest floor up. A
source file may include the private header of its own room or of a room below it, never of a
room above: so the rooms form no circle. Every folder of engine/src must be a room of this list,
and every room must have its header, which says what the room owns.

Usage: check_engine_rooms.py [ENGINE_SRC]   (default: engine/src beside this script's folder)
Exits 1 and names each include that runs back up.
"""
import pathlib
import re
import sys

# lowest floor first; each room's header is ROOM/HEADER
ROOMS = [
    ("basics", "basics.hpp"),                  # MuJoCo's constants, quaternion operations
    ("model", "model_room.hpp"),               # the field table expanded, Data's sizing, entry checks
    ("smooth", "smooth.hpp"),                  # kinematics, recursions, CRBA, RNEA, passive, actuation
    ("collision", "collision_room.hpp"),       # the collision stage and its narrow phase
    ("constraint", "constraint_room.hpp"),     # rows, products, solvers, contact forces
    ("sensors", "sensors.hpp"),                # sensor stages, forces inside the tree, rays
    ("derivatives", "derivatives_room.hpp"),   # the smooth dynamics differentiated (RNEA's)
    ("pipeline", "pipeline.hpp"),              # forward, the integrators, the batch
    ("transition", "transition.hpp"),          # forward dynamics and the step differentiated
    ("lifecycle", "lifecycle.hpp"),            # validate() and set_const()
    ("identification", "identification.hpp"),  # the regressor, base parameters, parameter vectors
]

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.M)


def main() -> int:
    src = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else (
        pathlib.Path(__file__).resolve().parent.parent / "engine" / "src")
    floor = {name: i for i, (name, _) in enumerate(ROOMS)}
    problems = []
    for name, header in ROOMS:
        if not (src / name / header).is_file():
            problems.append(f"room {name}/ has no header {header}")
    for folder in sorted(p for p in src.iterdir() if p.is_dir()):
        if folder.name not in floor:
            problems.append(f"{folder.name}/ is not a room of scripts/check_engine_rooms.py's list")
    for path in sorted(src.rglob("*")):
        if path.suffix not in (".cpp", ".hpp") or path.parent == src:
            if path.suffix in (".cpp", ".hpp"):
                problems.append(f"{path.relative_to(src)} is outside every room")
            continue
        room = path.relative_to(src).parts[0]
        for target in INCLUDE.findall(path.read_text()):
            if target in floor and room in floor and floor[target] > floor[room]:
                problems.append(f"{path.relative_to(src)} ({room}) includes {target}/: an arrow back up")
    for line in problems:
        print(line)
    if not problems:
        print(f"{len(ROOMS)} rooms, every include runs down or stays in its room")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
