"""examples/python/ray_sweep.py on a real local Ray cluster: a head and two worker nodes started
as separate processes on 127.0.0.1 (each stopped at the end through its own process group), the
model shipped once per worker; the states it steps equal a single-process BatchRunner's bit for
bit. Needs pip's `ray`, which make test does not install (about 360 MB, a minute to install):
`make test-ray` installs it into <build>/venv-ray beside make test's wheel and runs this file;
elsewhere (make test's venv) it is skipped."""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
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


def wait_for_head(head: subprocess.Popen, port: int, seconds: float = 60) -> None:
    """Until the head's port answers; fails at once if the head's `ray start` has exited."""
    deadline = time.time() + seconds
    while True:
        assert head.poll() is None, "the head's `ray start` exited (its output is not kept: run it by hand)"
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            assert time.time() < deadline, "the head did not answer"
            time.sleep(0.5)


@pytest.fixture
def cluster(monkeypatch):
    """A head without CPUs for tasks and two worker nodes of one CPU each, on 127.0.0.1."""
    port = free_port()
    ray_cmd = os.path.join(os.path.dirname(sys.executable), "ray")
    common = ["--block", "--disable-usage-stats"]
    # Ray's unix sockets live under its temp dir, whose path must stay within 107 bytes: a short
    # one of this run's own (pytest's tmp_path is too long)
    temp_dir = tempfile.mkdtemp(prefix="lever-ray-", dir="/tmp")
    # a local cluster without token authentication, whatever ~/.ray holds (`ray start` turns it
    # on when it finds a token there, ray.init does not: the driver could not connect)
    monkeypatch.setenv("RAY_AUTH_MODE", "disabled")
    nodes = [subprocess.Popen(
        [ray_cmd, "start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}",
         "--num-cpus=0", "--include-dashboard=false", f"--temp-dir={temp_dir}", *common],
        start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    address = f"127.0.0.1:{port}"
    try:
        wait_for_head(nodes[0], port)
        for worker in range(2):
            # each node its own temp dir: nodes on one machine sharing one would give their object
            # stores the same socket, and the second would abort
            nodes.append(subprocess.Popen(
                [ray_cmd, "start", f"--address={address}", "--node-ip-address=127.0.0.1",
                 "--num-cpus=1", f"--temp-dir={temp_dir}/w{worker}", *common],
                start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        ray.init(address=address, _node_ip_address="127.0.0.1", logging_level="error")
        deadline = time.time() + 120
        while ray.cluster_resources().get("CPU", 0) < 2:
            assert all(node.poll() is None for node in nodes), "a node's `ray start` exited"
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
        for node in nodes:  # a node drains for up to 30 s after SIGTERM: nothing is left to drain
            try:
                node.wait(timeout=5)
            except subprocess.TimeoutExpired:
                os.killpg(node.pid, signal.SIGKILL)
                node.wait()
        shutil.rmtree(temp_dir, ignore_errors=True)


def test_states_on_two_workers_equal_one_process_bit_for_bit(cluster):
    model = lever.load(str(REPO / "models" / "arm2.xml"))
    qpos, qvel = ray_sweep.random_states(model, 2000)
    alone = lever.BatchRunner(model, threads=1).step(qpos, qvel, nstep=ray_sweep.STEPS)
    spread = ray_sweep.sweep_on_ray(model, qpos, qvel, workers=2, chunk=250)
    assert np.array_equal(spread[0], alone[0]) and np.array_equal(spread[1], alone[1])
    assert ray_sweep.penetration(model, alone[0]).max() > 0  # some states ran into a stop
