"""What calling lever from Python costs: one forward() of a model from Python (the package's own
binding, and lever.mujoco's mj_forward) against the same call from C++ (lever_bench's
forward/<model>/lever, Google Benchmark), in one run. Prints a Markdown table of medians.

Run (after a build): PYTHONPATH=build/python /usr/bin/python3 bench/python_call_overhead.py \
    build/bench/lever_bench [models/arm2.xml ...]
"""
import json
import pathlib
import statistics
import subprocess
import sys
import timeit

import lever
import lever.mujoco as mujoco


def python_times(path: str, repeats: int = 15, number: int = 20000) -> dict:
    model = lever.load(path)
    data = lever.Data(model)
    mj_model = mujoco.MjModel.from_xml_path(path)
    mj_data = mujoco.MjData(mj_model)
    calls = {
        "lever.forward (binding)": lambda: lever.forward(model, data),
        "lever.mujoco.mj_forward": lambda: mujoco.mj_forward(mj_model, mj_data),
    }
    return {name: statistics.median(timeit.repeat(f, repeat=repeats, number=number)) / number
            for name, f in calls.items()}


def cpp_time(bench: str, name: str) -> float:
    out = subprocess.run([bench, f"--benchmark_filter=^forward/{name}/lever$",
                          "--benchmark_repetitions=15", "--benchmark_format=json",
                          "--benchmark_display_aggregates_only=true"],
                         capture_output=True, text=True, check=True).stdout
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3}[b["time_unit"]]
            return b["real_time"] * scale
    raise RuntimeError("no median in lever_bench's output")


def main() -> None:
    bench = sys.argv[1]
    models = sys.argv[2:] or ["models/arm2.xml", "models/arm7.xml"]
    print("| model | C++ forward | lever.forward from Python | mj_forward from lever.mujoco |")
    print("|---|---|---|---|")
    for path in models:
        name = pathlib.Path(path).stem
        cpp = cpp_time(bench, name)
        py = python_times(path)
        binding, compat = py["lever.forward (binding)"], py["lever.mujoco.mj_forward"]
        print(f"| {name} | {cpp * 1e9:.0f} ns | {binding * 1e9:.0f} ns ({binding / cpp:.1f}x, "
              f"+{(binding - cpp) * 1e9:.0f} ns) | {compat * 1e9:.0f} ns ({compat / cpp:.1f}x, "
              f"+{(compat - cpp) * 1e9:.0f} ns) |")


if __name__ == "__main__":
    main()
