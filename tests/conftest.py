"""Shared test configuration: paths, golden files, and the xacro 2.1.1 oracle."""

from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, settings

from tests.ray_cluster import cluster as cluster  # the fixture of the --ray tests
from tests.waiting import DEADLINE

TESTS = Path(__file__).parent
DATA = TESTS / "data"
REPO = TESTS.parent
EXAMPLES = REPO / "examples"


# Hypothesis fails an example slower than 200 ms and data generation it finds slow: clock
# checks that a busy machine trips. Tests assert results, not times. The test command draws the
# same examples every run, so a run's verdict is the code's; `--hypothesis-profile explore`
# draws new ones to hunt for failures.
settings.register_profile("explore", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("belvedere", settings.get_profile("explore"), derandomize=True)
settings.load_profile("belvedere")


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--update-golden",
        action="store_true",
        help="rewrite golden files under tests/data from the current output",
    )


@pytest.fixture
def update_golden(request: pytest.FixtureRequest) -> bool:
    return bool(request.config.getoption("--update-golden"))


def _oracle_version() -> str | None:
    try:
        return importlib.metadata.version("xacro")
    except importlib.metadata.PackageNotFoundError:
        return None


@dataclass(frozen=True)
class OracleResult:
    returncode: int
    stdout: str
    stderr: str


class Oracle:
    """Runs a reference xacro in a subprocess, imported from ``pythonpath`` first."""

    def __init__(self, pythonpath: Path) -> None:
        self.pythonpath = pythonpath

    def run(
        self, file: str, *args: str, cwd: Path, packages: dict[str, Path] | None = None
    ) -> OracleResult:
        env = dict(os.environ)
        env["PYTHONPATH"] = str(self.pythonpath)
        env["BELVEDERE_ORACLE_PACKAGES"] = os.pathsep.join(
            f"{name}={path}" for name, path in (packages or {}).items()
        )
        proc = subprocess.run(
            [sys.executable, "-c", "import xacro; xacro.main()", file, *args],
            cwd=cwd,
            env=env,
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        return OracleResult(proc.returncode, proc.stdout, proc.stderr)


MELODIC_ORACLE = REPO / ".oracles" / "xacro-1.13.3"


@pytest.fixture(scope="session")
def oracle() -> Oracle:
    """xacro 2.1.1 from the test environment (with a stand-in package index for $(find))."""
    version = _oracle_version()
    if version != "2.1.1":
        pytest.skip(f"xacro 2.1.1 (the reference) is not installed (found {version})")
    return Oracle(TESTS / "oracle_shim")


@pytest.fixture(scope="session")
def melodic_oracle() -> Oracle:
    """ROS Melodic's xacro 1.13.3, installed apart by scripts/install.sh --dev."""
    if not (MELODIC_ORACLE / "xacro" / "__init__.py").is_file():
        pytest.skip("xacro 1.13.3 (ROS Melodic's) is not installed under .oracles/")
    return Oracle(MELODIC_ORACLE)


TEST_DOMAIN = 231
"""The domain every test joins (never 0, the user's): see ``own_graph``."""


def free_port() -> int:
    """A free loopback TCP port."""
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def free_endpoint() -> str:
    """A free loopback endpoint."""
    return f"tcp/127.0.0.1:{free_port()}"


@pytest.fixture(autouse=True)
def own_graph(monkeypatch: pytest.MonkeyPatch) -> str:
    """Every test joins a graph of its own: a free loopback endpoint and a domain that is
    not 0, so the suite never meets a user's graph (tools and subprocesses see them too)."""
    value = free_endpoint()
    monkeypatch.setenv("BELVEDERE_ENDPOINT", value)
    monkeypatch.setenv("BELVEDERE_DOMAIN", str(TEST_DOMAIN))
    return value


@pytest.fixture(autouse=True)
def own_log_dir(monkeypatch: pytest.MonkeyPatch, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where launches write ROS's logs (``ROS_LOG_DIR``): never the user's ``~/.ros/log``."""
    path = tmp_path_factory.mktemp("ros_log")
    monkeypatch.setenv("ROS_LOG_DIR", str(path))
    return path


@pytest.fixture
def endpoint(own_graph: str) -> str:
    """This test's endpoint (``BELVEDERE_ENDPOINT``)."""
    return own_graph


PEER_SCRIPT = """
import sys, time
from belvedere.graph import Graph, ZenohTransport
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1]))
g.params.set("/robot/speed", 0.5)
n = g.create_node("peer")
n.service("trigger", "std_srvs/Trigger", lambda req: {"success": True, "message": "done"})
n.publisher("/map_name", "std_msgs/String", latch=True).publish_data({"data": "office"})
echo = n.publisher("/cmd_echo", "geometry_msgs/Twist")
n.subscribe("/cmd_vel", "geometry_msgs/Twist", echo.publish)
chatter = n.publisher("/chatter", "std_msgs/String")
n.timer(0.02, lambda: chatter.publish_data({"data": "tick"}))
from belvedere.tf import static_transform_publisher
static_transform_publisher(n, ["0.1", "0", "0.2", "1.5707963", "0", "0", "base_link", "camera"])
g.start(rtf=None)
print("READY", flush=True)
sys.stdin.read()
g.shutdown()
"""


@pytest.fixture
def peer(endpoint: str, tmp_path: Path) -> Any:
    """Another process on the graph: a service, a latched topic, a ticking topic, an echo of
    /cmd_vel on /cmd_echo, the parameter /robot/speed, and a static transform
    base_link -> camera."""
    script = tmp_path / "peer.py"
    script.write_text(PEER_SCRIPT)
    proc = subprocess.Popen(
        [sys.executable, str(script), endpoint],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "READY"
    yield proc
    assert proc.stdin is not None
    proc.stdin.close()
    proc.wait(timeout=DEADLINE)


@pytest.fixture
def full_disk(tmp_path: Path) -> Iterator[Path]:
    """A directory on a real, tiny file system (a 64 KiB tmpfs): a write of more fails with
    "No space left on device". Needs root and mount; skips where they are not allowed."""
    mount = tmp_path / "small"
    mount.mkdir()
    argv = ["mount", "-t", "tmpfs", "-o", "size=64k,mode=0755", "tmpfs", str(mount)]
    try:
        made = subprocess.run(argv, capture_output=True, text=True, check=False)
    except FileNotFoundError:
        pytest.skip("no mount command here")
    if made.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {made.stderr.strip() or made.returncode}")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], check=False)
