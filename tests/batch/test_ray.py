"""``belvedere batch --ray``: the runs as Ray tasks on a two-node cluster the test starts
(one CPU each, on 127.0.0.1, no dashboard), the same rows as local workers give."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES
from tests.ray_cluster import HOST, free_port
from tests.waiting import DEADLINE

ray_cluster_utils = pytest.importorskip("ray.cluster_utils", reason="Ray is not installed")

MBOT = EXAMPLES / "mbot_description" / "urdf" / "urdf" / "mbot_base.urdf"

SPEC = f"""\
sim: [{MBOT}]
duration: 2
runs:
  pub:
    - "/cmd_vel geometry_msgs/Twist {{linear: {{x: 0.2}}}}"
    - "/cmd_vel geometry_msgs/Twist {{linear: {{x: 0.3}}, angular: {{z: 0.5}}}}"
  seed: [1, 2]
record:
  x: /odom pose.pose.position.x
  y: /odom pose.pose.position.y
metrics:
  n_odom: count /odom
  far: python metrics.py:far /odom
"""

# shipped to the workers in the spec's folder (Ray's working_dir), as a user's package is
METRICS = """\
def far(messages):
    return max(m["pose"]["pose"]["position"]["x"] for m in messages["/odom"])
"""


def _batch(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "belvedere", "batch", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=DEADLINE * 2,
        check=False,
    )


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(f)]


def test_ray_gives_the_rows_local_workers_give(cluster: str, tmp_path: Path) -> None:
    (tmp_path / "metrics.py").write_text(METRICS)
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC)
    local = _batch(spec, "-o", tmp_path / "local.csv", "--workers", "2", cwd=tmp_path)
    assert local.returncode == 0, local.stderr
    on_ray = _batch(spec, "-o", tmp_path / "ray.csv", "--ray", cluster, cwd=tmp_path)
    assert on_ray.returncode == 0, on_ray.stderr
    assert "batch: 4/4 done, 0 failed" in on_ray.stderr
    rows = _rows(tmp_path / "ray.csv")
    assert [r["status"] for r in rows] == ["ok"] * 4
    assert float(rows[0]["x"]) == pytest.approx(0.4)  # 0.2 m/s for 2 simulated seconds
    assert float(rows[0]["far"]) == pytest.approx(0.4)
    assert float(rows[2]["y"]) > 0  # the arc turns left
    assert rows == _rows(tmp_path / "local.csv")


def test_no_cluster_at_the_address_is_one_clear_error(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(f"sim: [{MBOT}]\nduration: 1\n")
    ran = _batch(spec, "-o", "out.csv", "--ray", f"{HOST}:{free_port()}", cwd=tmp_path)
    assert ran.returncode == 1
    assert f"error: --ray {HOST}:" in ran.stderr
    assert "Traceback" not in ran.stderr


LOSES_ITS_WORKER = """\
import os
import signal
from pathlib import Path

MARK = Path({mark!r})


def once(messages):
    # the first attempt's worker dies mid-run, as on a lost machine; Ray runs it again
    if not MARK.exists():
        MARK.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return len(messages["/odom"])


def always(messages):
    os.kill(os.getpid(), signal.SIGKILL)
"""


def test_a_run_whose_worker_is_lost_is_run_again(cluster: str, tmp_path: Path) -> None:
    (tmp_path / "metrics.py").write_text(LOSES_ITS_WORKER.format(mark=str(tmp_path / "died")))
    spec = tmp_path / "spec.yaml"
    spec.write_text(f"sim: [{MBOT}]\nduration: 1\nmetrics:\n  n: python metrics.py:once /odom\n")
    ran = _batch(spec, "-o", tmp_path / "out.csv", "--ray", cluster, cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert (tmp_path / "died").exists()  # the first attempt's worker did die
    rows = _rows(tmp_path / "out.csv")
    assert [r["status"] for r in rows] == ["ok"]
    assert int(rows[0]["n"]) > 0


def test_a_run_that_loses_every_worker_is_a_lost_row(cluster: str, tmp_path: Path) -> None:
    (tmp_path / "metrics.py").write_text(LOSES_ITS_WORKER.format(mark=str(tmp_path / "died")))
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        f"sim: [{MBOT}]\nduration: 1\nruns:\n  seed: [1, 2]\n"
        "metrics:\n  n: python metrics.py:always /odom\n"
    )
    ran = _batch(spec, "-o", tmp_path / "out.csv", "--ray", cluster, cwd=tmp_path)
    rows = _rows(tmp_path / "out.csv")
    assert [r["status"] for r in rows] == ["lost", "lost"], ran.stderr
    assert all(r["error"].startswith("Ray: ") for r in rows)
    assert "Traceback" not in ran.stderr
