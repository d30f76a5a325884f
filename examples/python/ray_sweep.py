"""Lesson 5.1's stop penetration over many random starts, spread over processes with Ray.

INPUT arm2.xml; N random starting states (joint positions within the ranges, velocities up to
4 rad/s), the motors off
PROCESS each state falls for 0.5 s (250 steps); the deepest penetration past a joint stop is
read from the final states. The model goes to the cluster once (ray.put); one actor per worker
process holds it with a lever.BatchRunner, and each task steps a chunk of states in that runner.
The same sweep in one process (a BatchRunner of 1 and of 2 threads) gives the same numbers bit
for bit: every state is stepped by the same code on the same model.
OUTPUT states per second on 1 thread, 2 threads and the Ray workers; the deepest penetration

Run on this machine (Ray starts a local cluster of its own):
    python examples/python/ray_sweep.py --states 100000 --workers 2
Against a running cluster (`ray start --head` on one machine, `ray start --address=HEAD:6379` on
the others; every node needs `pip install` of the same lever and ray):
    python examples/python/ray_sweep.py --address HEAD:6379 --workers 8
"""
import argparse
import time

import numpy as np
import ray

import lever
from mjcourse import model_path

STEPS = 250


def random_states(model: lever.Model, n: int, seed: int = 7):
    """n starting states: positions uniform within each joint's range, velocities within 4 rad/s."""
    rng = np.random.default_rng(seed)
    lo, hi = model.jnt_range.T
    qpos = rng.uniform(lo, hi, size=(n, model.nq))
    qvel = rng.uniform(-4.0, 4.0, size=(n, model.nv))
    return qpos, qvel


def penetration(model: lever.Model, qpos: np.ndarray) -> np.ndarray:
    """How far each state is past a joint stop (rad; 0 within the range), per state."""
    lo, hi = model.jnt_range.T
    return np.maximum(0.0, np.maximum(lo - qpos, qpos - hi)).max(axis=1)


@ray.remote(num_cpus=1)
class Stepper:
    """One per worker process: the model (unpickled once) and a BatchRunner of one thread."""

    def __init__(self, model: lever.Model):
        self.runner = lever.BatchRunner(model, threads=1)

    def step(self, qpos: np.ndarray, qvel: np.ndarray, nstep: int):
        return self.runner.step(qpos, qvel, nstep=nstep)


def sweep_on_ray(model: lever.Model, qpos: np.ndarray, qvel: np.ndarray, workers: int,
                 chunk: int = 5000):
    """The states stepped by `workers` Ray actors, chunk by chunk; rows in the input's order."""
    model_ref = ray.put(model)  # shipped once; each actor unpickles it once
    steppers = [Stepper.remote(model_ref) for _ in range(workers)]
    starts = range(0, len(qpos), chunk)
    pending = [steppers[k % workers].step.remote(qpos[s:s + chunk], qvel[s:s + chunk], STEPS)
               for k, s in enumerate(starts)]
    results = ray.get(pending)
    return np.vstack([q for q, _ in results]), np.vstack([v for _, v in results])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=100_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--address", default=None, help="a running cluster (default: a local one)")
    args = parser.parse_args()

    model = lever.load(str(model_path("arm2")))
    qpos, qvel = random_states(model, args.states)
    rates = {}
    single = None
    for threads in (1, 2):
        runner = lever.BatchRunner(model, threads=threads)
        start = time.perf_counter()
        out = runner.step(qpos, qvel, nstep=STEPS)
        rates[f"1 process, {threads} thread{'s' if threads > 1 else ''}"] = \
            args.states / (time.perf_counter() - start)
        if single is None:
            single = out
        assert np.array_equal(out[0], single[0]) and np.array_equal(out[1], single[1])

    ray.init(address=args.address, num_cpus=None if args.address else args.workers,
             include_dashboard=False, logging_level="error")
    sweep_on_ray(model, qpos[:10], qvel[:10], args.workers)  # actors and workers started
    start = time.perf_counter()
    on_ray = sweep_on_ray(model, qpos, qvel, args.workers)
    rates[f"Ray, {args.workers} workers"] = args.states / (time.perf_counter() - start)
    ray.shutdown()
    same = np.array_equal(on_ray[0], single[0]) and np.array_equal(on_ray[1], single[1])

    print(f"{args.states} states of arm2, {STEPS} steps each (0.5 s), motors off")
    for what, rate in rates.items():
        print(f"  {what:24s} {rate:10.0f} states/s")
    print(f"  Ray's final states equal the single process's bit for bit: {same}")
    print(f"  after 0.5 s, the deepest past a stop: {penetration(model, single[0]).max() * 1e3:.2f} mrad")


if __name__ == "__main__":
    main()
