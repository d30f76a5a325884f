"""examples/python/ray_sweep.py on a real local Ray cluster: a head and two worker nodes started
as separate processes on 127.0.0.1 (each stopped at the end through its own process group), the
model shipped once per worker; the states it steps equal a single-process BatchRunner's bit for
bit. Needs pip's `ray`, which make test does not install (about 300 MB and minutes to install);
run it with ray installed beside the package (docs/python.md)."""
import os
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import REPO

ray = pytest.importorskip("ray")
sys.path.insert(0, str(REPO / "examples" / "python"))
import ray_sweep  # noqa: E402  (the example itself)

import lever  # noqa: E402


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def cluster(tmp_path):
    """A head without CPUs for tasks and two worker nodes of one CPU each, on 127.0.0.1."""
    port = free_port()
    ray_cmd = os.path.join(os.path.dirname(sys.executable), "ray")
    common = ["--block", "--disable-usage-stats"]
    nodes = [subprocess.Popen(
        [ray_cmd, "start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}",
         "--num-cpus=0", "--include-dashboard=false", f"--temp-dir={tmp_path}", *common],
        start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    address = f"127.0.0.1:{port}"
    time.sleep(5)
    for _ in range(2):
        nodes.append(subprocess.Popen(
            [ray_cmd, "start", f"--address={address}", "--node-ip-address=127.0.0.1",
             "--num-cpus=1", *common],
            start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    try:
        ray.init(address=address, logging_level="error")
        deadline = time.time() + 120
        while ray.cluster_resources().get("CPU", 0) < 2:
            assert time.time() < deadline, "the two worker nodes did not join"
            time.sleep(1)
        assert len([n for n in ray.nodes() if n["Alive"]]) == 3
        yield address
    finally:
        ray.shutdown()
        for node in nodes:  # each node's processes, by the group its `ray start` leads
            try:
                os.killpg(node.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        for node in nodes:
            node.wait(timeout=60)


def test_states_on_two_workers_equal_one_process_bit_for_bit(cluster):
    model = lever.load(str(REPO / "models" / "arm2.xml"))
    qpos, qvel = ray_sweep.random_states(model, 4000)
    alone = lever.BatchRunner(model, threads=1).step(qpos, qvel, nstep=ray_sweep.STEPS)
    spread = ray_sweep.sweep_on_ray(model, qpos, qvel, workers=2, chunk=500)
    assert np.array_equal(spread[0], alone[0]) and np.array_equal(spread[1], alone[1])
    assert ray_sweep.penetration(model, alone[0]).max() > 0  # some states ran into a stop
