#!/usr/bin/env python3
"""Instructions per call of every benchmarked operation, counted by callgrind.

    bench/instructions.py --profile build-bench/bench/lever_bench_profile \
        [--iterations N] [--stages arm2,panda7,chain20,mesh_gripper] [--jobs 2] [--commit ID] \
        --out build-bench/instructions.json models/*.xml bench/scenes/*.xml

Runs `lever_bench_profile MODEL --all N` under `valgrind --tool=callgrind --instr-atstart=no`,
once per model: every operation's loop is dumped on its own, and an empty loop first measures the
loop itself. Instructions per call = (the loop's total - the empty loop's per-iteration cost x N) / N.
The counts are exact and do not depend on the machine's load: after three warm-up calls every call
runs the same instructions, so N = 1000 and N = 11000 give the same count per call. For the
models named by --stages, the `forward` loops are also broken down (and lever's `step`): lever's by
function (self cost, `callgrind_annotate --inclusive=no`), MuJoCo's by the stages of its pipeline (inclusive cost of
mj_kinematics, mj_comPos, ..., mj_fwdConstraint: libmujoco's own static functions have no names).

Writes one JSON file, which `lever_bench_report --instructions FILE` puts beside the times:
  {"tool": ..., "iterations": N, "seconds": ...,
   "models": {"arm2": {"lever": {"forward": 4214.0, ...}, "mujoco": {...}, "kdl": {...}}},
   "stages": {"arm2": {"lever": [["lever::poses", 878.0], ...], "lever_step": [...],
                       "mujoco": [["mj_kinematics", ...]]}}}
Needs Debian's valgrind (callgrind and callgrind_annotate).
"""
import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


def fail(message):
    print(f"instructions.py: {message}", file=sys.stderr)
    sys.exit(2)


TRIGGER = "desc: Trigger: Client Request: "  # CALLGRIND_DUMP_STATS_AT's label


def read_dump(path):
    """(operation, total instructions) of one callgrind dump."""
    name, total = None, None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith(TRIGGER):
                name = line[len(TRIGGER):].strip()
            elif line.startswith("totals:"):
                total = int(line.split()[1])
    return name, total


# a line of callgrind_annotate's function list: "  1,234 (12.34%)  file:function [object]"
ANNOTATE_LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$")


def short_name(symbol):
    """A function's readable name: no object file, no source file, no argument list."""
    symbol = re.sub(r"\s+\[[^\]]*\]$", "", symbol)  # " [/path/to/object]"
    if ":" in symbol and not symbol.startswith("::"):
        head, rest = symbol.split(":", 1)
        if not rest.startswith(":"):  # "file:function", not "ns::function"
            symbol = rest
    symbol = symbol.replace("(anonymous namespace)::", "")
    depth, cut = 0, len(symbol)
    for i, c in enumerate(symbol):  # the argument list: the first '(' outside template brackets
        if c == "<":
            depth += 1
        elif c == ">":
            depth -= 1
        elif c == "(" and depth == 0 and i > 0:
            cut = i
            break
    symbol = symbol[:cut].strip()
    # a function template's instance, which the demangler writes with its return type first:
    # "void lever::forward_pass<...a lambda's type...>" -> "lever::forward_pass"
    instance = re.match(r"^[\w:]+ ([\w:]+)<.*>$", symbol)
    if instance:
        symbol = instance.group(1)
    return symbol


# MuJoCo 2.2.2's forward pipeline, the functions mj_forward's stages call (none calls another)
MUJOCO_STAGES = [
    "mj_kinematics", "mj_comPos", "mj_camlight", "mj_tendon", "mj_transmission", "mj_crb",
    "mj_factorM", "mj_collision", "mj_makeConstraint", "mj_projectConstraint", "mj_sensorPos",
    "mj_energyPos", "mj_comVel", "mj_passive", "mj_referenceConstraint", "mj_rne", "mj_sensorVel",
    "mj_energyVel", "mj_fwdActuation", "mj_fwdAcceleration", "mj_fwdConstraint", "mj_sensorAcc",
]
# the loop around the operation (lever_bench_profile's own), measured by the empty loop
HARNESS = re.compile(r"^(count|std::_Function_handler<.*)$")


def annotate(dump, iterations, inclusive):
    """Instructions per call of every function in one dump, {name: count}."""
    out = subprocess.run(
        ["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}", "--threshold=100",
         "--auto=no", dump], check=True, capture_output=True, text=True).stdout
    costs = {}
    in_functions = False
    for line in out.splitlines():
        if "file:function" in line:
            in_functions = True
            continue
        m = ANNOTATE_LINE.match(line) if in_functions else None
        if m and "PROGRAM TOTALS" not in line:
            name = short_name(m.group(2))
            costs[name] = costs.get(name, 0) + int(m.group(1).replace(",", "")) / iterations
    return costs


def lever_stages(dump, iterations):
    """lever's functions by self cost per call, dearest first (the loop left out)."""
    costs = annotate(dump, iterations, inclusive=False)
    return sorted(([name, round(c, 1)] for name, c in costs.items()
                   if c > 0 and not HARNESS.match(name)), key=lambda item: -item[1])


def mujoco_stages(dump, iterations, per_call):
    """MuJoCo's forward by pipeline stage (inclusive cost per call), in the pipeline's order;
    what is left (mj_forward's own work, mj_checkPos/Vel/Acc, ...) as "rest"."""
    costs = annotate(dump, iterations, inclusive=True)
    out = [[name, round(costs[name], 1)] for name in MUJOCO_STAGES if costs.get(name, 0) > 0]
    out.append(["rest", round(per_call - sum(c for _, c in out), 1)])
    return out


def count_model(profile, model_path, iterations, want_stages, workdir):
    name = os.path.splitext(os.path.basename(model_path))[0]
    out_file = os.path.join(workdir, f"callgrind.{name}.out")
    run = subprocess.run(
        ["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out_file}",
         profile, model_path, "--all", str(iterations)],
        capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"{model_path}: lever_bench_profile failed under valgrind:\n"
                           f"{run.stdout}{run.stderr}")
    loops = {}  # operation -> iterations
    for line in run.stdout.splitlines():
        parts = line.split("\t")
        if len(parts) == 2:
            loops[parts[0]] = int(parts[1])
    dumps = {}
    for entry in os.listdir(workdir):
        if entry.startswith(os.path.basename(out_file) + "."):
            op, total = read_dump(os.path.join(workdir, entry))
            if op in loops and total is not None:
                dumps[op] = (total, os.path.join(workdir, entry))
    missing = sorted(set(loops) - set(dumps))
    if missing or "empty" not in dumps:
        raise RuntimeError(f"{model_path}: no callgrind dump for {', '.join(missing) or 'empty'}")
    loop_cost = dumps["empty"][0] / loops["empty"]  # per iteration: the loop and the call
    counts = {"lever": {}, "mujoco": {}, "kdl": {}, "pinocchio": {}}
    for op, n in loops.items():
        if op == "empty":
            continue
        peer, _, bare = op.rpartition(":")
        per_call = (dumps[op][0] - loop_cost * n) / n
        counts[peer or "lever"][bare] = round(per_call, 1)
    # lever's analytic Jacobian is the peer of both of MuJoCo's finite differences (one call)
    if "step_jacobian_forward" in counts["lever"]:
        counts["lever"]["step_jacobian_centred"] = counts["lever"]["step_jacobian_forward"]
    breakdown = None
    if want_stages:
        breakdown = {
            "lever": lever_stages(dumps["forward"][1], loops["forward"]),
            "lever_step": lever_stages(dumps["step"][1], loops["step"]),
            "mujoco": mujoco_stages(dumps["mujoco:forward"][1], loops["mujoco:forward"],
                                    counts["mujoco"]["forward"]),
        }
    return name, counts, breakdown, round(loop_cost, 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="+", help="model files (MJCF)")
    parser.add_argument("--profile", required=True, help="the lever_bench_profile executable")
    parser.add_argument("--out", required=True, help="the JSON file to write")
    parser.add_argument("--iterations", type=int, default=1000)
    parser.add_argument("--stages", default="arm2,panda7,chain20,mesh_gripper",
                        help="models whose forward is broken down by function (comma-separated)")
    parser.add_argument("--jobs", type=int, default=2, help="models counted at once")
    parser.add_argument("--commit", default="unknown", help="lever's commit, for the report")
    args = parser.parse_args()
    if args.iterations < 1:
        fail("--iterations must be at least 1")
    for tool in ("valgrind", "callgrind_annotate"):
        if shutil.which(tool) is None:
            fail(f"{tool} not found (Debian: valgrind; scripts/setup.sh bench installs it)")
    if not os.access(args.profile, os.X_OK):
        fail(f"{args.profile} is not an executable (build the lever_bench_profile target)")
    want = set(filter(None, args.stages.split(",")))
    version = subprocess.run(["valgrind", "--version"], capture_output=True, text=True).stdout

    start = time.monotonic()
    result = {"tool": "callgrind (" + version.strip() + ")", "lever_commit": args.commit,
              "iterations": args.iterations,
              "models": {}, "stages": {}, "loop": {}}
    with tempfile.TemporaryDirectory(prefix="lever-instructions-") as tmp:
        jobs = []
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for i, path in enumerate(args.models):
                name = os.path.splitext(os.path.basename(path))[0]
                workdir = os.path.join(tmp, str(i))
                os.mkdir(workdir)
                jobs.append(pool.submit(count_model, args.profile, path, args.iterations,
                                        name in want, workdir))
            try:
                for job in jobs:
                    name, counts, breakdown, loop_cost = job.result()
                    result["models"][name] = counts
                    result["loop"][name] = loop_cost
                    if breakdown:
                        result["stages"][name] = breakdown
                    print(f"instructions.py: {name}: {sum(map(len, counts.values()))} operations "
                          f"counted", file=sys.stderr)
            except RuntimeError as e:
                fail(str(e))
    result["seconds"] = round(time.monotonic() - start, 1)
    # written at the end only, then renamed: a failed run leaves no half file behind
    with open(args.out + ".part", "w", encoding="utf-8") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    os.replace(args.out + ".part", args.out)
    print(f"instructions.py: wrote {args.out} in {result['seconds']} s", file=sys.stderr)


if __name__ == "__main__":
    main()
