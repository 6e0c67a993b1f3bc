"""Reading launch files: the roslaunch language and its errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.errors import ParseError
from belvedere.launch import LaunchError, load_launch
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES


def _launch(tmp_path: Path, text: str, name: str = "test.launch", **args: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _load(path: Path, **args: str) -> object:
    return load_launch(path, args=args, packages=PackageIndex([EXAMPLES]))


def test_args_params_groups_remaps_and_substitutions(tmp_path: Path) -> None:
    inner = _launch(
        tmp_path,
        """<launch>
          <arg name="speed"/>
          <param name="speed" value="$(arg speed)"/>
          <node pkg="tf" type="static_transform_publisher" name="$(anon stp)"
                args="0 0 0 0 0 0 a b 100"/>
        </launch>""",
        "inner.launch",
    )
    path = _launch(
        tmp_path,
        f"""<launch>
          <arg name="robot" default="mbot"/>
          <arg name="fast" default="false"/>
          <arg name="scale" value="2"/>
          <param name="name" value="$(arg robot)"/>
          <param name="ratio" type="double" value="3"/>
          <param name="flag" value="True"/>
          <param name="twice" value="$(eval 2 * scale + (10 if fast else 0))"/>
          <param name="here" value="$(dirname)"/>
          <param name="pkg" value="$(find mbot_description)"/>
          <param name="home" value="$(optenv NO_SUCH_VARIABLE fallback value)"/>
          <group ns="robot1" if="$(eval robot == 'mbot')">
            <remap from="cmd_vel" to="/teleop/cmd_vel"/>
            <node pkg="robot_state_publisher" type="robot_state_publisher" name="rsp">
              <param name="publish_frequency" value="20"/>
              <rosparam>
                gains: {{p: 1.5, d: 0.1}}
              </rosparam>
            </node>
            <include file="{inner}" ns="sub">
              <arg name="speed" value="0.5"/>
            </include>
          </group>
          <group unless="$(arg fast)">
            <param name="slow" value="yes"/>
          </group>
          <rosparam param="list">[1, 2, 3]</rosparam>
          <test test-name="t" pkg="x" type="y"/>
          <machine name="far" address="10.0.0.1"/>
        </launch>""",
    )
    config = _load(path, fast="true")
    params = {k: p.value for k, p in config.params.items()}  # type: ignore[attr-defined]
    assert params["/name"] == "mbot"
    assert params["/ratio"] == 3.0
    assert params["/flag"] is True
    assert params["/twice"] == 14
    assert params["/here"] == str(tmp_path)
    assert params["/pkg"] == str(EXAMPLES / "mbot_description")
    assert params["/home"] == "fallback value"
    assert params["/robot1/rsp/publish_frequency"] == 20
    assert params["/robot1/rsp/gains/p"] == 1.5
    assert params["/robot1/sub/speed"] == 0.5
    assert params["/list"] == [1, 2, 3]
    assert "/slow" not in params  # unless fast
    nodes = config.nodes  # type: ignore[attr-defined]
    rsp = nodes[0]
    assert (rsp.full_name, rsp.remappings) == ("/robot1/rsp", (("cmd_vel", "/teleop/cmd_vel"),))
    assert nodes[1].namespace == "/robot1/sub"
    assert nodes[1].name.startswith("stp_")
    warnings = " ".join(config.warnings)  # type: ignore[attr-defined]
    assert "<test> t skipped" in warnings
    assert "<machine far> ignored" in warnings
    assert config.files == [("launch", str(path)), ("launch", str(inner))]  # type: ignore[attr-defined]


def test_xacro_command_runs_in_process(tmp_path: Path) -> None:
    path = _launch(
        tmp_path,
        """<launch>
          <arg name="dir" value="$(find mbot_description)/urdf/xacro/gazebo"/>
          <param name="robot_description"
                 command="$(find xacro)/xacro --inorder '$(arg dir)/mbot_gazebo_modern.xacro'"/>
          <param name="legacy" command="xacro.py '$(arg dir)/mbot_gazebo.xacro'"/>
          <param name="echo" command="echo hello"/>
        </launch>""",
    )
    config = _load(path)
    params = config.params  # type: ignore[attr-defined]
    assert "<robot" in params["/robot_description"].value
    assert 'name="left_wheel_link"' in params["/legacy"].value
    assert params["/echo"].value == "hello\n"


@pytest.mark.parametrize(
    ("text", "args", "where", "message"),
    [
        ("<launch>\n  <arg name='x'/>\n</launch>", {}, ":2:", "required arg 'x' is not set"),
        (
            "<launch>\n  <arg name='x' default='1'/>\n</launch>",
            {"y": "1"},
            ":1:",
            "unused args ['y']",
        ),
        (
            "<launch>\n  <param name='p' value='$(arg nope)'/>\n</launch>",
            {},
            ":2:",
            "arg 'nope' is not defined",
        ),
        (
            "<launch>\n  <param name='p' value='$(what x)'/>\n</launch>",
            {},
            ":2:",
            "unknown substitution command $(what x)",
        ),
        ("<launch>\n  <include file='/no/such.launch'/>\n</launch>", {}, ":2:", "does not exist"),
        (
            "<launch>\n  <group if='maybe'/>\n</launch>",
            {},
            ":2:",
            "if='maybe': expected true, false, 1 or 0",
        ),
        (
            "<launch>\n  <rosparam>\n    a: [1,\n  </rosparam>\n</launch>",
            {},
            ":4:",
            "invalid YAML",
        ),
        (
            "<launch>\n<<<<<<< HEAD\n  <param name='a' value='1'/>\n=======\n>>>>>>> x\n</launch>",
            {},
            ":2:",
            "malformed XML",
        ),
        (
            "<launch>\n  <param name='p' value='1' type='float32'/>\n</launch>",
            {},
            ":2:",
            "unknown param type",
        ),
        (
            "<launch>\n  <param name='p' command='false'/>\n</launch>",
            {},
            ":2:",
            "command 'false' failed",
        ),
        ("<launch>\n  <node pkg='a' type='b'/>\n</launch>", {}, ":2:", "<node> needs a name"),
        ("<robot/>", {}, ":1:", "root must be <launch>"),
        (
            "<launch>\n  <param name='p' value='1.0e309'/>\n</launch>",
            {},
            ":2:3:",
            "param value '1.0e309' is not a finite number\n  hint: the largest double is "
            '±1.7976931348623157e+308; for text, add type="str"',
        ),
        (
            "<launch>\n  <param name='p' type='double' value='-inf'/>\n</launch>",
            {},
            ":2:3:",
            "param value '-inf' is not a finite number",
        ),
        (
            "<launch>\n  <node pkg='a' type='b' name='c' respawn_delay='soon'/>\n</launch>",
            {},
            ":2:3:",
            "param value 'soon' is not a valid double",
        ),
        (
            "<launch>\n  <rosparam file='/no/such.yaml'/>\n</launch>",
            {},
            ":2:3:",
            "cannot read YAML file '/no/such.yaml': No such file or directory",
        ),
        (
            "<launch>\n  <rosparam>\n    a: " + "9" * 5000 + "\n  </rosparam>\n</launch>",
            {},
            ":3:8:",
            "invalid YAML: Exceeds the limit (4300 digits) for integer string conversion",
        ),
    ],
)
def test_errors_name_file_and_line(
    tmp_path: Path, text: str, args: dict[str, str], where: str, message: str
) -> None:
    path = _launch(tmp_path, text)
    with pytest.raises(ParseError) as info:
        _load(path, **args)
    described = info.value.describe()
    assert f"{path}{where}" in described
    assert message in described


def test_conflict_markers_get_a_hint(tmp_path: Path) -> None:
    path = _launch(tmp_path, "<launch>\n<<<<<<< HEAD\n</launch>\n")
    with pytest.raises(ParseError, match="malformed XML") as info:
        _load(path)
    assert "git conflict markers at line(s) 2" in info.value.describe()


def test_include_cycle(tmp_path: Path) -> None:
    a = tmp_path / "a.launch"
    b = tmp_path / "b.launch"
    a.write_text(f"<launch><include file='{b}'/></launch>")
    b.write_text(f"<launch><include file='{a}'/></launch>")
    with pytest.raises(LaunchError, match="include cycle"):
        _load(a)


def test_gazebo_empty_world_is_built_in() -> None:
    config = load_launch(
        EXAMPLES / "mbot_gazebo/launch/view_mbot_gazebo_empty_world.launch",
        args={"gui": "false", "paused": "true"},
        packages=PackageIndex([EXAMPLES]),
    )
    kinds = [(n.pkg, n.type) for n in config.nodes]
    assert ("gazebo_ros", "gzserver") in kinds
    assert ("gazebo_ros", "gzclient") not in kinds  # gui:=false
    server = config.node("/gazebo")
    assert server is not None
    assert server.args.startswith("-u ")  # paused
    assert server.args.endswith("mbot_gazebo/worlds/empty.world")
    assert config.params["/use_sim_time"].value is True


@pytest.mark.parametrize(
    ("expr", "message", "at"),
    [
        # the escape reported against xacro, spelt for roslaunch's $(eval)
        ("vars(type)['_'+'_subclasses_'+'_']", "name 'vars' is not defined", None),
        ("'a'.upper._self", "the attribute '_self' is not allowed", "._self"),
        ("str.mro()", "attribute 'mro' of a type value is not available", ".mro"),
        ("(x for x in []).gi_frame.f_globals", "attribute 'gi_frame' of a generator", ".gi_"),
        ("9**9**9", "9 ** 387420489 is too large", "9**9**9"),
        ("'{0.real}'.format(1)", "format field '{0.real}' is not allowed", "'{0."),
    ],
)
def test_eval_runs_in_the_sandbox(tmp_path: Path, expr: str, message: str, at: str | None) -> None:
    line = f'  <param name="p" value="$(eval {expr})"/>'
    path = _launch(tmp_path, f"<launch>\n{line}\n</launch>")
    with pytest.raises(LaunchError) as info:
        _load(path)
    described = info.value.describe()
    assert message in described
    col = 3 if at is None else line.index(at) + 1
    assert described.startswith(f"{path}:2:{col}: error: $(eval "), described


def test_groups_nested_beyond_the_limit_are_one_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from belvedere.cli import main

    ok = _launch(tmp_path, "<launch>" + "<group>" * 255 + "</group>" * 255 + "</launch>")
    assert _load(ok) is not None
    text = "<launch>" + "<group>" * 496 + "<param name='a' value='1'/>" + "</group>" * 496
    path = _launch(tmp_path, text + "</launch>", "deep.launch")
    assert main(["launch", str(path)]) == 1
    err = capsys.readouterr().err
    column = len("<launch>") + 255 * len("<group>") + 1
    assert err == (
        f"{path}:1:{column}: error: elements nest more than 256 levels deep (the nesting limit)\n"
        "  hint: no robot, world or launch file needs as many\n"
    )


def test_roslaunch_scoping_rules(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The rules the differential tests check against roslaunch, here without it."""
    from belvedere.cli import main

    path = _launch(
        tmp_path,
        """<launch>
  <param name="~early" value="1"/>
  <param name="use gui" value="true"/>
  <param name="text" value="1e5"/>
  <group ns="g">
    <param name="~in_group" value="2"/>
    <remap from="a" to="b"/>
    <node pkg="p" type="t" name="n" args="x 'y z'">
      <param name="/slash" value="3"/>
      <rosparam>{"/k": 4, j: 5}</rosparam>
      <remap from="a" to="c"/>
      <env name="BELVEDERE_TEST_E" value="v w"/>
    </node>
  </group>
  <node pkg="p" type="t" name="later"/>
  <test test-name="a_test" pkg="p" type="t"/>
</launch>""",
    )
    config = load_launch(path, packages=PackageIndex([EXAMPLES]))
    params = {k: p.value for k, p in config.params.items()}
    assert params == {
        "/use gui": True,
        "/text": "1e5",
        "/k": 4,
        "/g/n/j": 5,
        "/g/n/early": 1,
        "/g/n/in_group": 2,
        "/g/n/slash": 3,
        "/later/early": 1,
        "/a_test/early": 1,
    }
    assert f"{path}:3:3: warning: parameter name 'use gui' is not a legal ROS name" in " ".join(
        config.warnings
    )
    assert main(["launch", str(path), "--nodes"]) == 0
    assert capsys.readouterr().out == "/g/n\n/later\n/a_test\n"
    assert main(["launch", str(path), "--dump-params"]) == 0
    assert capsys.readouterr().out.startswith("/a_test/early: 1\n/g/n/early: 1\n")
    assert main(["launch", str(path), "--args", "/g/n"]) == 0
    out = capsys.readouterr().out
    assert out.endswith(' ROS_NAMESPACE="/g" BELVEDERE_TEST_E="v w" p/t x y z a:=c __name:=n\n'), (
        out
    )


def test_a_rosparam_value_remembers_its_yaml_line(tmp_path: Path) -> None:
    """A node that refuses a loaded value can name the YAML line it came from."""
    (tmp_path / "planner.yaml").write_text(
        "controller_frequency: 3.0\n\nTrajectoryPlannerROS:\n  max_vel_x: 0.5\n  sim_time: 1.0\n"
    )
    launch = tmp_path / "nav.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="move_base" type="move_base" name="move_base">\n'
        f'    <rosparam file="{tmp_path / "planner.yaml"}" command="load"/>\n'
        '    <rosparam ns="extra">\n      a: 1\n      b: {c: 2}\n    </rosparam>\n'
        '    <param name="base_local_planner" value="nope"/>\n'
        "  </node>\n</launch>\n"
    )
    params = load_launch(launch).params
    source = params["/move_base/TrajectoryPlannerROS/sim_time"].source
    assert str(source) == f"{tmp_path / 'planner.yaml'}:5:13"
    assert str(params["/move_base/controller_frequency"].source).endswith("planner.yaml:1:23")
    assert str(params["/move_base/extra/b/c"].source) == f"{launch}:6:14"
    assert str(params["/move_base/base_local_planner"].source) == f"{launch}:8:5"
