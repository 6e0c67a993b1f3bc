"""A local two-node Ray cluster for the tests of ``--ray`` (``belvedere batch``, ``belvedere
test``): one CPU each, on 127.0.0.2, no dashboard."""

from __future__ import annotations

import socket
from collections.abc import Iterator

import pytest

__all__ = ["HOST", "cluster", "free_port"]

HOST = "127.0.0.2"
"""Ray takes 127.0.0.1 for "this machine" and swaps in its network address; 127.0.0.2 stays."""


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind((HOST, 0))
        port: int = sock.getsockname()[1]
    return port


@pytest.fixture(scope="module")
def cluster() -> Iterator[str]:
    """A head and a second node, one CPU each: a task per node at a time; its address."""
    ray_cluster_utils = pytest.importorskip("ray.cluster_utils", reason="Ray is not installed")
    made = ray_cluster_utils.Cluster(
        initialize_head=True,
        head_node_args={
            "num_cpus": 1,
            "gcs_server_port": free_port(),
            "include_dashboard": False,
            "node_ip_address": HOST,
        },
    )
    made.add_node(num_cpus=1, node_ip_address=HOST)
    made.wait_for_nodes()
    try:
        yield f"{HOST}:{made.address.rpartition(':')[2]}"
    finally:
        made.shutdown()
