"""``belvedere batch``: a spec's runs as headless processes, one CSV row each.

The runs are the kinematic mbot (ArbotiX's fake mode integrates /cmd_vel exactly), so the
rows' values are known: 0.2 m/s for 3 simulated seconds is 0.6 m.
"""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

from belvedere.batch import read_spec, run_local
from belvedere.errors import ParseError
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description" / "urdf" / "urdf" / "mbot_base.urdf"

SPEC = f"""\
sim: [{MBOT}]
duration: 3
runs:
  pub:
    - "/cmd_vel geometry_msgs/Twist {{linear: {{x: 0.2}}}}"
    - "/cmd_vel geometry_msgs/Twist {{linear: {{x: 0.4}}, angular: {{z: 0.5}}}}"
  seed: [1, 2]
record:
  x: /odom pose.pose.position.x
  frame: /odom header.frame_id
metrics:
  top_speed: max /odom twist.twist.linear.x
  n_odom: count /odom
  t_half: time /odom pose.pose.position.x >= 0.5
  path: python metrics.py:path_length /odom
"""

METRICS = """\
import math

def path_length(messages):
    points = [(m["pose"]["pose"]["position"]["x"], m["pose"]["pose"]["position"]["y"])
              for m in messages["/odom"]]
    return sum(math.dist(a, b) for a, b in zip(points, points[1:]))
"""


def _spec(tmp_path: Path, text: str = SPEC) -> Path:
    (tmp_path / "metrics.py").write_text(METRICS)
    path = tmp_path / "spec.yaml"
    path.write_text(text)
    return path


def _batch(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "belvedere", "batch", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def test_the_rows_are_the_runs_and_the_same_whatever_the_worker_count(tmp_path: Path) -> None:
    spec = _spec(tmp_path)
    one = _batch(spec, "-o", tmp_path / "one.csv", "--workers", "1", cwd=tmp_path)
    assert one.returncode == 0, one.stderr
    two = _batch(
        spec, "-o", tmp_path / "two.csv", "--workers", "2", "--plot", "p.png", cwd=tmp_path
    )
    assert two.returncode == 0, two.stderr
    assert "batch: 4/4 done, 0 failed" in two.stderr
    rows = _rows(tmp_path / "one.csv")
    assert list(rows[0]) == [
        "run", "pub", "seed", "status", "error", "wall_s",
        "x", "frame", "top_speed", "n_odom", "t_half", "path",
    ]  # fmt: skip
    assert [r["run"] for r in rows] == ["0", "1", "2", "3"]
    assert [r["seed"] for r in rows] == ["1", "2", "1", "2"]
    assert {r["status"] for r in rows} == {"ok"}
    straight = rows[0]
    assert float(straight["x"]) == pytest.approx(0.6)
    # the first /odom (at 0.1 s, ArbotiX's 10 Hz) is 0.02 m along already
    assert float(straight["path"]) == pytest.approx(0.6 - 0.02)
    assert float(straight["top_speed"]) == pytest.approx(0.2)
    assert float(straight["t_half"]) == pytest.approx(2.5)  # 0.5 m at 0.2 m/s
    assert straight["frame"] == "odom"
    assert int(straight["n_odom"]) > 0
    turning = rows[2]
    assert float(turning["path"]) == pytest.approx(1.2 - 0.04)  # 0.4 m/s on an arc
    assert float(turning["x"]) < 1.2  # the arc bends away from x
    assert float(turning["t_half"]) < 2.5

    def without_wall(rs: list[dict[str, str]]) -> list[dict[str, str]]:
        return [{k: v for k, v in r.items() if k != "wall_s"} for r in rs]

    assert without_wall(rows) == without_wall(_rows(tmp_path / "two.csv"))
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_failing_or_timed_out_run_is_a_row_not_the_end(tmp_path: Path) -> None:
    spec = _spec(
        tmp_path,
        f"""\
sim: [{MBOT}]
duration: 2
runs:
  seed: [1]
metrics:
  scans: count /scan
""",
    )
    done = _batch(spec, "-o", "out.csv", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    (row,) = _rows(tmp_path / "out.csv")
    assert row["status"] == "failed"
    assert "--echo /scan: no node in this run publishes" in row["error"]
    assert row["scans"] == ""
    slow = _spec(tmp_path, f"sim: [{MBOT}]\nduration: 100000\ntimeout: 1\n")
    rows = run_local(read_spec(slow), 1, lambda _: None)
    assert [(r["status"], r["error"]) for r in rows] == [
        ("timeout", "stopped after 1 s of wall-clock time")
    ]


def test_a_launch_run_gets_its_args_params_and_a_bag(tmp_path: Path) -> None:
    spec = _spec(
        tmp_path,
        f"""\
launch: [mbot_description, arbotix_mbot_with_laser_xacro.launch, --package-path, {EXAMPLES}]
duration: 1
runs:
  params: {{/batch_test/gain: [1.5, 3]}}
record:
  x: /odom pose.pose.position.x
bag: true
goal: map 1.0 0.5 0
""",
    )
    done = _batch(spec, "-o", "out.csv", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    rows = _rows(tmp_path / "out.csv")
    assert [(r["param:/batch_test/gain"], r["status"]) for r in rows] == [
        ("1.5", "ok"),
        ("3", "ok"),
    ], rows
    assert float(rows[0]["x"]) == 0.0  # nothing drove it
    bags = sorted((tmp_path / "out.bags").iterdir())
    assert [b.name for b in bags] == ["run-0000.bag", "run-0001.bag"]
    assert bags[0].read_bytes().startswith(b"#ROSBAG V2.0")


@pytest.mark.parametrize(
    ("text", "line", "says"),
    [
        ("sim: [m.urdf]\nduration: 1\nruns:\n  speed: [1]\n", 4, "unknown key 'speed' in runs:"),
        ("sim: [m.urdf]\nduration: -1\n", 2, "duration: expects a positive number"),
        ("sim: [m.urdf]\nduration: 1\nrecord:\n  x: /odom\n", 4, "expects 'TOPIC FIELD'"),
        ("sim: [m.urdf]\nduration: 1\nmetrics:\n  x: median /odom a\n", 4, "unknown metric"),
        (
            "sim: [m.urdf]\nduration: 1\nruns:\n  params: {a: [1]}\n",
            4,
            "params: needs launch:",
        ),
        (
            "sim: [m.urdf]\nduration: 1\nruns:\n  pub: ['/cmd_vel geometry_msgs/Twist {x: 1}']\n",
            4,
            "geometry_msgs/Twist",
        ),
        ("sim: [m.urdf, --rtf, '2']\nduration: 1\n", 1, "--rtf is set by the batch"),
        ("launch: a b\nduration: 1\ngoal: map 1\n", 3, "goal: expects 'FRAME X Y YAW'"),
        ("duration: 1\n", 1, "names one of sim: or launch:"),
    ],
)
def test_a_spec_error_names_its_file_and_line(
    tmp_path: Path, text: str, line: int, says: str
) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ParseError) as caught:
        read_spec(path)
    assert caught.value.location is not None
    assert caught.value.location.line == line
    assert says in caught.value.message


def test_the_command_line_says_a_spec_error_without_a_traceback(tmp_path: Path) -> None:
    (tmp_path / "bad.yaml").write_text("sim: [m.urdf]\nduration: 1\nbag: yes please\n")
    done = _batch("bad.yaml", "-o", "out.csv", cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.startswith("bad.yaml:3:6: error: bag: expects true or false")
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "out.csv").exists()
