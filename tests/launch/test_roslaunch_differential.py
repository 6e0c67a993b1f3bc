"""``belvedere launch --dump-params | --nodes | --args NODE`` against Debian's roslaunch
(ros_comm 1.15) on the example launch files and on generated ones that exercise every scoping
rule: the same lines, so the same parameters (names, values and types), nodes and commands.

Skipped where ``/usr/bin/roslaunch`` is absent (``scripts/install.sh --dev`` installs it)."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import yaml

from belvedere.cli import main
from belvedere.launch import load_launch
from belvedere.launch._listing import summary
from belvedere.packages import BUILTIN_PACKAGES
from tests.conftest import EXAMPLES, MELODIC_ORACLE

ROSLAUNCH = Path("/usr/bin/roslaunch")
SYSTEM_PYTHON = Path("/usr/bin/python3")

_PACKAGE_XML = (
    "<package><name>{name}</name><version>0.0.0</version><description>d</description>"
    '<maintainer email="m@example.com">m</maintainer><license>BSD</license></package>\n'
)


@dataclass(frozen=True)
class Workspace:
    """A package path both sides search: a package with executables, an xacro stand-in."""

    root: Path
    env: dict[str, str]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def _package(root: Path, name: str, executables: dict[str, str], *, under: str = "") -> Path:
    pkg = root / name
    (pkg / under).mkdir(parents=True, exist_ok=True)
    (pkg / "package.xml").write_text(_PACKAGE_XML.format(name=name))
    for exe, text in executables.items():
        path = pkg / under / exe
        path.write_text(text)
        path.chmod(0o755)
    return pkg


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Workspace:
    if not ROSLAUNCH.is_file():
        pytest.skip(f"{ROSLAUNCH} (Debian's ROS 1 roslaunch, the reference) is not installed")
    root = tmp_path_factory.mktemp("ws")
    _package(
        root / "src",
        "gen_pkg",
        {"talker": "#!/bin/sh\n", "listener": "#!/bin/sh\n"},
        under="scripts",
    )
    # roslaunch runs <param command="$(find xacro)/xacro …">: ROS Melodic's xacro, the dialect
    # of the course's files, stands in (belvedere runs its own xacro in process)
    shim = f"#!{SYSTEM_PYTHON}\nimport sys\nsys.path[0] = {str(MELODIC_ORACLE)!r}\n"
    shim += "import xacro\nxacro.main()\n"
    _package(root / "src", "xacro", {"xacro": shim, "xacro.py": shim})
    package_path = os.pathsep.join([str(root / "src"), str(EXAMPLES), str(BUILTIN_PACKAGES)])
    env = {
        "ROS_HOME": str(root / "ros_home"),
        "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}/",
        "ROS_PACKAGE_PATH": package_path,
        "BELVEDERE_PACKAGE_PATH": package_path,
        "GEN_TEST_VALUE": "from the environment",
    }
    return Workspace(root, env)


@pytest.fixture
def both(workspace: Workspace, monkeypatch: pytest.MonkeyPatch) -> Workspace:
    """The workspace's environment, set here too (``--args`` prints what differs from it)."""
    for key, value in workspace.env.items():
        monkeypatch.setenv(key, value)
    monkeypatch.delenv("ROS_NAMESPACE", raising=False)
    return workspace


# roslaunch's own entry point, called once per option line in one process per launch file
# (its start-up costs more than its work): the same code `roslaunch OPTIONS FILE` runs
_DRIVER = """
import contextlib, io, json, sys
import roslaunch
results = []
for argv in json.load(sys.stdin):
    out, err = io.StringIO(), io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            roslaunch.main(["roslaunch", *argv])
        except SystemExit as exit:
            code = exit.code if isinstance(exit.code, int) else 1
    results.append({"code": code, "out": out.getvalue(), "err": err.getvalue()})
json.dump(results, sys.stdout)
"""


@dataclass(frozen=True)
class Run:
    code: int
    out: str
    err: str


def _roslaunch_runs(path: Path, *option_lines: tuple[str, ...]) -> list[Run]:
    env = dict(os.environ)
    env["PATH"] = "/usr/bin" + os.pathsep + env.get("PATH", "")
    done = subprocess.run(
        [str(SYSTEM_PYTHON), "-c", _DRIVER],
        input=json.dumps([[*options, str(path)] for options in option_lines]),
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    return [Run(**r) for r in json.loads(done.stdout)]


def _roslaunch(path: Path, *options: str) -> str:
    (run,) = _roslaunch_runs(path, options)
    assert run.code == 0, run.err
    assert "Unable to load file" not in run.err, run.err  # --dump-params exits 0 then
    return run.out


def _belvedere(path: Path, capsys: pytest.CaptureFixture[str], *options: str) -> str:
    capsys.readouterr()
    code = main(["launch", str(path), *options])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def _xml(text: str) -> Any:
    """A URDF as a tree (comments, namespace declarations and layout left out)."""

    def tree(el: ET.Element) -> Any:
        return (el.tag, sorted(el.attrib.items()), (el.text or "").strip(), [tree(c) for c in el])

    return tree(ET.fromstring(text.encode()))


def _same_params(real: str, ours: str, *, exact: bool) -> int:
    """Compare two ``--dump-params`` outputs: the text itself when ``exact``, else every
    parameter by name, type and value (XML values as trees). Returns how many there are."""
    if exact:
        assert ours == real
    expected, got = yaml.safe_load(real) or {}, yaml.safe_load(ours) or {}
    assert sorted(got) == sorted(expected)
    for name, value in expected.items():
        assert type(got[name]) is type(value), name
        if isinstance(value, str) and value.lstrip().startswith("<?xml"):
            assert _xml(got[name]) == _xml(value), name
        else:
            assert got[name] == value, name
    return len(expected)


def _compare(
    path: Path, capsys: pytest.CaptureFixture[str], *, generated: bool
) -> tuple[int, int, int]:
    """``--dump-params``, ``--nodes`` and ``--args`` of each node, from both; on generated
    files (whose executables both find) every line must be the same, on the examples the
    parameters must be (XML by tree) and the command lines apart from where Debian installed
    the executable. Returns the parameters, nodes and command lines compared."""
    names = _belvedere(path, capsys, "--nodes").split()
    ours = {name: _belvedere(path, capsys, "--args", name) for name in names}
    # roslaunch can only say "Cannot locate node" for nodes Debian does not have
    asked = names if generated else [n for n in names if _installed(ours[n])]
    dump, nodes, *args = _roslaunch_runs(
        path, ("--dump-params",), ("--nodes",), *[("--args", name) for name in asked]
    )
    for run in (dump, nodes, *args):
        assert run.code == 0, run.err
    assert "Unable to load file" not in dump.err, dump.err  # --dump-params exits 0 then
    count = _same_params(dump.out, _belvedere(path, capsys, "--dump-params"), exact=generated)
    assert nodes.out == "\n".join(names) + "\n"
    for name, run in zip(asked, args, strict=True):
        if generated:
            assert ours[name] == run.out
        else:
            real_words, our_words = run.out.split(), ours[name].split()
            exe = next(i for i, w in enumerate(real_words) if w.startswith("/"))
            del real_words[exe], our_words[exe]
            assert our_words == real_words
    return count, len(names), len(asked)


def _installed(our_line: str) -> bool:
    """Whether Debian installed the node belvedere shows as ``PKG/TYPE`` (roslib finds it
    under ``/usr/lib/PKG``) or it is an executable file belvedere found."""
    word = next(w for w in our_line.split() if "=" not in w)
    return word.startswith("/") or (Path("/usr/lib") / word).is_file()


EXAMPLE_FILES = sorted(EXAMPLES.glob("*/launch/*.launch"))


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=[p.name for p in EXAMPLE_FILES])
def test_example_launch_files(
    path: Path, both: Workspace, capsys: pytest.CaptureFixture[str]
) -> None:
    if not (MELODIC_ORACLE / "xacro" / "__init__.py").is_file() or not SYSTEM_PYTHON.is_file():
        pytest.skip("ROS Melodic's xacro (under .oracles/) runs roslaunch's <param command>")
    # robot_description is xacro's text: its layout is xacro's business (tested there)
    params, nodes, _ = _compare(path, capsys, generated=False)
    assert params
    assert nodes


# --- generated launch files: one rule at a time, and all of them together ------------------

SCOPING = """<launch>
  <arg name="robot" default="bot"/>
  <arg name="on" default="true"/>
  <param name="~early" value="1"/>
  <param name="use gui" value="true"/>
  <param name="guess_exp" value="1e5"/>
  <param name="guess_underscore" value="1_000"/>
  <param name="guess_spaces" value=" 2.5 "/>
  <param name="guess_bool" value="True"/>
  <param name="guess_int" value="-7"/>
  <param name="typed_yaml" type="yaml" value="{a: 1, b: [1, 2.5, x]}"/>
  <param name="typed_str" type="str" value=" 12 "/>
  <param name="typed_double" type="double" value="3"/>
  <param name="typed_bool" type="bool" value="1"/>
  <param name="/absolute/p" value="a"/>
  <rosparam>{"/glob": 1, rel: 2, nested: {x: [1, 2], y: {z: yes}}}</rosparam>
  <rosparam param="listed">[1, two, 3.0]</rosparam>
  <rosparam ns="from_ns" param="p">{q: 5}</rosparam>
  <rosparam ns="/abs_ns">{r: 6}</rosparam>
  <rosparam command="load" ns="loaded" file="$(dirname)/gains.yaml"/>
  <rosparam command="load" param="/subst" subst_value="true">{who: $(arg robot)}</rosparam>
  <rosparam command="delete" param="never_there"/>
  <remap from="cmd_vel" to="/top/cmd_vel"/>
  <env name="GEN_TOP" value="top"/>
  <group ns="$(arg robot)">
    <param name="~in_group" value="g"/>
    <param name="ns_param" value="1" if="$(arg on)"/>
    <param name="skipped" value="1" unless="$(arg on)"/>
    <remap from="cmd_vel" to="group_cmd_vel"/>
    <remap from="scan" to="base_scan"/>
    <env name="GEN_GROUP" value="group"/>
    <node pkg="gen_pkg" type="talker" name="talker" ns="sub" args="--rate 10 'two words'">
      <param name="/slash" value="1"/>
      <param name="~tilde" value="2"/>
      <param name="plain" value="3"/>
      <param name="early" value="overridden"/>
      <rosparam>{"/k": 3, j: 4, "~t": 5}</rosparam>
      <rosparam ns="/abs" param="pp">{q: 5}</rosparam>
      <rosparam ns="rel" param="/pp">{q: 6}</rosparam>
      <rosparam param="private_list">[a, b]</rosparam>
      <remap from="cmd_vel" to="node_cmd_vel"/>
      <remap from="/odom" to="odom_filtered"/>
      <remap from="x" to="y" if="$(arg on)"/>
      <remap from="w" to="v" unless="$(arg on)"/>
      <env name="GEN_NODE" value="two words"/>
      <env name="GEN_GROUP" value="node wins"/>
    </node>
    <node pkg="gen_pkg" type="listener" name="listener" ns="/global_ns"/>
  </group>
  <param name="~late" value="after group"/>
  <node pkg="gen_pkg" type="listener" name="listener" launch-prefix="nice -n 5"/>
  <test test-name="scoping_test" pkg="gen_pkg" type="talker" name="tester">
    <param name="test_param" value="1"/>
  </test>
  <test test-name="unnamed_test" pkg="gen_pkg" type="talker"/>
</launch>
"""

GAINS = """p: 1.5
i: 0
d: [0.1, 0.2]
nested:
  deeper: {flag: false, name: gains}
"""

CHILD = """<launch>
  <arg name="speed"/>
  <arg name="robot" default="child_default"/>
  <param name="speed" value="$(arg speed)"/>
  <param name="robot" value="$(arg robot)"/>
  <param name="~from_child" value="leaks"/>
  <remap from="chatter" to="child_chatter"/>
  <node pkg="gen_pkg" type="talker" name="child_talker" args="$(arg speed)"/>
</launch>
"""

ALL_ARGS = """<launch>
  <arg name="speed"/>
  <arg name="robot"/>
  <arg name="extra" default="none"/>
  <param name="all" value="$(arg speed) $(arg robot) $(arg extra)"/>
  <node pkg="gen_pkg" type="listener" name="all_args_listener"/>
</launch>
"""

INCLUDES = """<launch>
  <arg name="speed" default="0.5"/>
  <arg name="robot" default="parent"/>
  <param name="~before" value="1"/>
  <remap from="chatter" to="parent_chatter"/>
  <env name="GEN_PARENT" value="p"/>
  <include file="$(dirname)/child.launch" ns="inc">
    <arg name="speed" value="$(arg speed)"/>
    <env name="GEN_INCLUDE" value="i"/>
  </include>
  <include file="$(dirname)/child.launch" ns="/abs_inc">
    <arg name="speed" value="2"/>
    <arg name="robot" value="given"/>
  </include>
  <include file="$(dirname)/all_args.launch" ns="all" pass_all_args="true"/>
  <group ns="grp">
    <include file="$(find gen_pkg)/child.launch">
      <arg name="speed" value="3.25"/>
    </include>
  </group>
  <node pkg="gen_pkg" type="listener" name="after_includes"/>
</launch>
"""

EMPTY_PRIVATE = """<launch>
  <group>
    <param name="~only_in_group" value="1"/>
    <node pkg="gen_pkg" type="talker" name="in_group"/>
  </group>
  <node pkg="gen_pkg" type="talker" name="after_group"/>
  <include file="$(dirname)/child.launch">
    <arg name="speed" value="1"/>
  </include>
  <node pkg="gen_pkg" type="listener" name="after_include"/>
</launch>
"""

SUBSTITUTIONS = """<launch>
  <arg name="base" default="3"/>
  <arg name="flag" default="false"/>
  <arg name="name" value="sub_$(arg base)"/>
  <param name="eval" value="$(eval base * 2 + 1)"/>
  <param name="eval_str" value="$(eval 'x' + name)"/>
  <param name="env" value="$(env GEN_TEST_VALUE)"/>
  <param name="optenv" value="$(optenv GEN_NOT_SET default words)"/>
  <param name="optenv_set" value="$(optenv GEN_TEST_VALUE)"/>
  <param name="find" value="$(find gen_pkg)/config"/>
  <param name="dirname" value="$(dirname)"/>
  <group if="$(eval not flag)">
    <param name="$(arg name)/inside" value="$(arg base).0"/>
    <node pkg="gen_pkg" type="talker" name="$(arg name)" args="--base $(arg base)">
      <param name="~double" value="$(eval float(base) / 2)"/>
    </node>
  </group>
  <group unless="$(eval not flag)">
    <node pkg="gen_pkg" type="talker" name="never"/>
  </group>
</launch>
"""

GENERATED = {
    "scoping.launch": SCOPING,
    "includes.launch": INCLUDES,
    "empty_private.launch": EMPTY_PRIVATE,
    "substitutions.launch": SUBSTITUTIONS,
}


@pytest.fixture(scope="module")
def generated(workspace: Workspace) -> Path:
    pkg = workspace.root / "src" / "gen_pkg"
    (pkg / "gains.yaml").write_text(GAINS)
    (pkg / "child.launch").write_text(CHILD)
    (pkg / "all_args.launch").write_text(ALL_ARGS)
    for name, text in GENERATED.items():
        (pkg / name).write_text(text)
    return pkg


@pytest.mark.parametrize("name", sorted(GENERATED))
def test_generated_launch_files(
    name: str, generated: Path, both: Workspace, capsys: pytest.CaptureFixture[str]
) -> None:
    params, nodes, commands = _compare(generated / name, capsys, generated=True)
    assert params
    assert nodes == commands


def test_the_scoping_rules_in_words(
    generated: Path, both: Workspace, capsys: pytest.CaptureFixture[str]
) -> None:
    """What the differential above establishes, spelt out (and checked against roslaunch)."""
    path = generated / "scoping.launch"
    params = yaml.safe_load(_roslaunch(path, "--dump-params"))
    ours = yaml.safe_load(_belvedere(path, capsys, "--dump-params"))
    node = "/bot/sub/talker"
    for expected in (
        f"{node}/slash",  # <param name="/x"> in a node is the node's
        f"{node}/tilde",
        f"{node}/early",  # a ~param outside a node reaches every later node …
        f"{node}/in_group",
        "/listener/late",  # … declared before it in its scope
        "/k",  # inline rosparam {"/k": v} in a node is global
        "/use gui",  # an illegal name is set as written
        "/tester/test_param",  # tests get their parameters too
    ):
        assert expected in params
        assert expected in ours
    assert params[f"{node}/early"] == ours[f"{node}/early"] == "overridden"
    assert "/listener/in_group" not in ours  # a group's ~params stay in the group
    assert _belvedere(path, capsys, "--nodes").split()[-2:] == ["/tester", "/unnamed_test"]
    err = capsys.readouterr().err
    assert err == ""
    main(["launch", str(path), "--nodes"])
    err = capsys.readouterr().err
    assert f"{path}:5:3: warning: parameter name 'use gui' is not a legal ROS name" in err


# --- the summary roslaunch prints before it starts anything ---------------------------------

# roslaunch's loader and summary, as `roslaunch FILE` runs them before starting the processes
# (`local=True`: no MACHINES section)
_SUMMARY_DRIVER = """
import json, sys
import roslaunch.config
out = []
for path in json.load(sys.stdin):
    config = roslaunch.config.load_config_default([path], None, verbose=False)
    out.append(config.summary(local=True) + "\\n")
json.dump(out, sys.stdout)
"""

ROSCORE_PARAMS = (" * /rosdistro: ", " * /rosversion: ")
"""Parameters roslaunch's roscore.xml sets on every launch (belvedere sets neither)."""

SUMMARY = """<launch>
  <param name="long" value="a value of more than twenty characters"/>
  <param name="exact" value="twenty characters ok"/>
  <param name="accented" value="café"/>
  <param name="late_accent" value="twenty characters and é"/>
  <param name="lines" textfile="$(dirname)/lines.txt"/>
  <param name="line" textfile="$(dirname)/line.txt"/>
  <param name="trailing_space" type="str" value="ends in spaces   "/>
  <param name="flag" value="true"/>
  <param name="number" value="2.50"/>
  <param name="mapping" type="yaml" value="{a: 1, b: [x, 2.5]}"/>
  <rosparam param="listed">[1, two, 3.0]</rosparam>
  <node pkg="gen_pkg" type="talker" name="top" clear_params="true">
    <param name="p" value="1"/>
  </node>
  <group ns="zeta" clear_params="true">
    <node pkg="gen_pkg" type="listener" name="b_node"/>
    <node pkg="gen_pkg" type="talker" name="a_node" ns="deeper"/>
  </group>
  <node pkg="gen_pkg" type="listener" name="abs" ns="/alpha"/>
</launch>
"""


def _roslaunch_summaries(*paths: Path) -> list[str]:
    env = dict(os.environ)
    env["PATH"] = "/usr/bin" + os.pathsep + env.get("PATH", "")
    done = subprocess.run(
        [str(SYSTEM_PYTHON), "-c", _SUMMARY_DRIVER],
        input=json.dumps([str(p) for p in paths]),
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    texts: list[str] = json.loads(done.stdout)
    return [
        "".join(line for line in text.splitlines(True) if not line.startswith(ROSCORE_PARAMS))
        for text in texts
    ]


def test_the_summary_is_roslaunchs(generated: Path, both: Workspace) -> None:
    """Line for line the summary roslaunch prints, on generated files (clearing, every kind
    of value, namespaces) and on the examples (their xacro run by ROS Melodic's xacro there,
    by belvedere's here: the 20 characters shown are the same)."""
    (generated / "summary.launch").write_text(SUMMARY)
    (generated / "lines.txt").write_text("line one\nline two\n")
    (generated / "line.txt").write_text("one line\n")
    paths = [generated / "summary.launch", *(generated / n for n in sorted(GENERATED))]
    if (MELODIC_ORACLE / "xacro" / "__init__.py").is_file():
        paths += EXAMPLE_FILES
    expected = _roslaunch_summaries(*paths)
    lines = 0
    for path, text in zip(paths, expected, strict=True):
        assert summary(load_launch(path)) == text, path
        lines += text.count("\n")
    assert lines > 300
    assert expected[0] == (
        "\nSUMMARY\n========\n\nCLEAR PARAMETERS\n * /top/\n * /zeta/\n\nPARAMETERS\n"
        " * /accented: <...>\n * /exact: twenty characters ok\n * /flag: True\n"
        " * /late_accent: twenty characters...\n * /line: one line\n * /lines: <...>\n"
        " * /listed: [1, 'two', 3.0]\n"
        " * /long: a value of more t...\n * /mapping: {'a': 1, 'b': ['x...\n * /number: 2.5\n"
        " * /top/p: 1\n * /trailing_space: ends in spaces\n\nNODES\n  /\n"
        "    top (gen_pkg/talker)\n  /alpha/\n    abs (gen_pkg/listener)\n  /zeta/\n"
        "    b_node (gen_pkg/listener)\n  /zeta/deeper/\n    a_node (gen_pkg/talker)\n\n"
    )
