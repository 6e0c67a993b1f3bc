"""xacro speed: belvedere against the reference xacro 2.1.1, in the same run.

Generates macro-heavy robots (ARMS arms x 50 nested segments: a recursive segment macro with
xacro:if and blocks, an inertia macro, a YAML load, an include) in two shapes — ``flat``
(properties and blocks) and ``cfg`` (every dimension read from a nested YAML config as
``cfg.segment.length``, ~40 expressions per segment) — expands each with both, checks the
outputs are byte-identical, and prints CPU seconds and the ratio for 10, 20 and 40 arms.
Then a 300-deep nesting, which 2.1.1 cannot expand.

    python benchmarks/xacro_speed.py [--arms 10 20 40] [--segments 50] [--shape flat|cfg|both]

Both run as separate processes (interpreter start-up included for both); CPU time is the
children's user+sys time.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COMMON = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="box_inertial" params="m x y z">
    <inertial>
      <mass value="${m}"/>
      <inertia ixx="${m*(y*y+z*z)/12}" ixy="0" ixz="0" iyy="${m*(x*x+z*z)/12}" iyz="0"
               izz="${m*(x*x+y*y)/12}"/>
    </inertial>
  </xacro:macro>
  <xacro:macro name="motor" params="name parent m:=0.05 *origin">
    <link name="${name}">
      <visual>
        <geometry><box size="0.02 0.02 0.03"/></geometry>
      </visual>
      <xacro:box_inertial m="${m}" x="0.02" y="0.02" z="0.03"/>
    </link>
    <joint name="${name}_mount" type="fixed">
      <parent link="${parent}"/>
      <child link="${name}"/>
      <xacro:insert_block name="origin"/>
    </joint>
  </xacro:macro>
  <material name="m0"><color rgba="1 0 0 1"/></material>
  <material name="m1"><color rgba="0 1 0 1"/></material>
  <material name="m2"><color rgba="0 0 1 1"/></material>
</robot>
"""

CONFIG = """seg_len: 0.1
seg_mass: 0.25
radius: !millimeters 20
twist: !degrees 1.5
"""

ROBOT = """<?xml version="1.0"?>
<robot name="bench" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="common.xacro"/>
  <xacro:property name="cfg" value="${{xacro.load_yaml('config.yaml')}}"/>
  <xacro:property name="segs" value="{segments}"/>
  <link name="base_link"/>
  <xacro:macro name="segment" params="arm n parent *geom">
    <link name="arm${{arm}}_seg${{n}}">
      <visual>
        <origin xyz="0 0 ${{cfg.seg_len/2}}" rpy="0 0 0"/>
        <xacro:insert_block name="geom"/>
        <material name="m${{n % 3}}"/>
      </visual>
      <collision>
        <origin xyz="0 0 ${{cfg.seg_len/2}}" rpy="0 0 0"/>
        <xacro:insert_block name="geom"/>
      </collision>
      <xacro:box_inertial m="${{cfg.seg_mass}}" x="${{2*cfg.radius}}" y="${{2*cfg.radius}}"
                          z="${{cfg.seg_len}}"/>
    </link>
    <joint name="arm${{arm}}_joint${{n}}" type="revolute">
      <parent link="${{parent}}"/>
      <child link="arm${{arm}}_seg${{n}}"/>
      <origin xyz="0 0 ${{cfg.seg_len if n > 1 else 0}}" rpy="0 0 ${{n*cfg.twist}}"/>
      <axis xyz="${{n % 2}} ${{1 - n % 2}} 0"/>
      <limit lower="${{-pi/2}}" upper="${{pi/2}}" effort="${{10 + n}}" velocity="1.0"/>
    </joint>
    <xacro:motor name="arm${{arm}}_motor${{n}}" parent="arm${{arm}}_seg${{n}}">
      <origin xyz="${{cfg.radius}} 0 ${{cfg.seg_len * 0.25}}" rpy="0 ${{pi/2}} 0"/>
    </xacro:motor>
    <xacro:if value="${{n &lt; segs}}">
      <xacro:segment arm="${{arm}}" n="${{n+1}}" parent="arm${{arm}}_seg${{n}}">
        <xacro:insert_block name="geom"/>
      </xacro:segment>
    </xacro:if>
  </xacro:macro>
{arms}
</robot>
"""

# The shape of robots whose every dimension comes from a YAML config read with dotted access
# (cfg.segment.length), with ~40 expressions per segment: the evaluator's hot path.
CONFIG_NESTED = """segment:
  length: 0.1
  mass: 0.25
  radius: !millimeters 20
  twist: !degrees 1.5
  color: [0.8, 0.2, 0.1, 1.0]
motor:
  mass: 0.05
  size: [0.02, 0.02, 0.03]
  offset: 0.25
limits:
  effort: 10
  velocity: 1.0
  lower: !degrees -90
  upper: !degrees 90
  damping: 0.7
sensor:
  rate: 50
  range: [0.05, 2.0]
"""

ROBOT_NESTED = """<?xml version="1.0"?>
<robot name="bench" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="cfg" value="${{xacro.load_yaml('config_nested.yaml')}}"/>
  <xacro:property name="segs" value="{segments}"/>
  <link name="base_link"/>
  <xacro:macro name="box_inertia" params="m x y z *origin">
    <inertial>
      <xacro:insert_block name="origin"/>
      <mass value="${{m}}"/>
      <inertia ixx="${{m*(y*y+z*z)/12}}" ixy="0" ixz="0" iyy="${{m*(x*x+z*z)/12}}" iyz="0"
               izz="${{m*(x*x+y*y)/12}}"/>
    </inertial>
  </xacro:macro>
  <xacro:macro name="segment" params="arm n parent side:=1 *geom">
    <xacro:property name="seg" value="${{cfg.segment}}"/>
    <xacro:property name="name" value="arm${{arm}}_seg${{n}}"/>
    <link name="${{name}}">
      <visual>
        <origin xyz="0 0 ${{seg.length/2}}" rpy="0 0 ${{side*seg.twist/2}}"/>
        <xacro:insert_block name="geom"/>
        <material name="c${{n % 3}}">
          <color rgba="${{seg.color[0]}} ${{seg.color[1]*n/segs}} ${{seg.color[2]}} 1"/>
        </material>
      </visual>
      <collision>
        <origin xyz="0 0 ${{seg.length/2}}" rpy="0 0 0"/>
        <xacro:insert_block name="geom"/>
      </collision>
      <xacro:box_inertia m="${{seg.mass}}" x="${{2*seg.radius}}" y="${{2*seg.radius}}"
                     z="${{seg.length}}">
        <origin xyz="0 0 ${{seg.length/2}}" rpy="0 0 0"/>
      </xacro:box_inertia>
    </link>
    <joint name="arm${{arm}}_joint${{n}}" type="${{'revolute' if n % 4 else 'continuous'}}">
      <parent link="${{parent}}"/>
      <child link="${{name}}"/>
      <origin xyz="0 0 ${{seg.length if n > 1 else 0}}" rpy="0 0 ${{n*seg.twist*side}}"/>
      <axis xyz="${{n % 2}} ${{1 - n % 2}} 0"/>
      <limit lower="${{cfg.limits.lower}}" upper="${{cfg.limits.upper}}"
             effort="${{cfg.limits.effort + n}}" velocity="${{cfg.limits.velocity}}"/>
      <dynamics damping="${{cfg.limits.damping * (1 + n/segs)}}" friction="0.0"/>
    </joint>
    <link name="${{name}}_motor">
      <visual>
        <geometry>
          <box size="${{cfg.motor.size[0]}} ${{cfg.motor.size[1]}} ${{cfg.motor.size[2]}}"/>
        </geometry>
      </visual>
      <xacro:box_inertia m="${{cfg.motor.mass}}" x="${{cfg.motor.size[0]}}"
                         y="${{cfg.motor.size[1]}}" z="${{cfg.motor.size[2]}}">
        <origin xyz="0 0 0" rpy="0 0 0"/>
      </xacro:box_inertia>
    </link>
    <joint name="${{name}}_motor_mount" type="fixed">
      <parent link="${{name}}"/>
      <child link="${{name}}_motor"/>
      <origin xyz="${{seg.radius}} 0 ${{seg.length * cfg.motor.offset}}" rpy="0 ${{pi/2}} 0"/>
    </joint>
    <gazebo reference="${{name}}">
      <sensor name="${{name}}_range" type="ray">
        <update_rate>${{cfg.sensor.rate}}</update_rate>
        <range min="${{cfg.sensor.range[0]}}" max="${{cfg.sensor.range[1]}}"/>
      </sensor>
    </gazebo>
    <xacro:if value="${{n &lt; segs}}">
      <xacro:segment arm="${{arm}}" n="${{n+1}}" parent="${{name}}" side="${{-side}}">
        <xacro:insert_block name="geom"/>
      </xacro:segment>
    </xacro:if>
  </xacro:macro>
{arms}
</robot>
"""

ARM = """  <xacro:segment arm="{i}" n="1" parent="base_link">
    <geometry><cylinder radius="${{cfg.radius}}" length="${{cfg.seg_len}}"/></geometry>
  </xacro:segment>"""


def write_robot(directory: Path, arms: int, segments: int, *, nested: bool = False) -> Path:
    """The benchmark robot: ``nested`` is the YAML-config shape, else the flat one."""
    (directory / "common.xacro").write_text(COMMON)
    (directory / "config.yaml").write_text(CONFIG)
    (directory / "config_nested.yaml").write_text(CONFIG_NESTED)
    kind = "cfg" if nested else "flat"
    robot = directory / f"robot_{kind}_{arms}x{segments}.xacro"
    arm = ARM.replace("cfg.", "cfg.segment.").replace("seg_len", "length") if nested else ARM
    body = "\n".join(arm.format(i=i) for i in range(arms))
    template = ROBOT_NESTED if nested else ROBOT
    robot.write_text(template.format(segments=segments, arms=body))
    return robot


def run(command: list[str], robot: Path) -> tuple[float, float, subprocess.CompletedProcess[str]]:
    """(cpu seconds, wall seconds, result) of one expansion in a fresh interpreter."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, *command, robot.name],
        cwd=robot.parent,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, proc


OURS = ["-m", "belvedere", "xacro"]
"""``belvedere xacro FILE``, as the installed command runs it."""
REFERENCE = ["-c", "import xacro; xacro.main()"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", type=int, nargs="+", default=[10, 20, 40])
    parser.add_argument("--segments", type=int, default=50)
    parser.add_argument(
        "--shape",
        choices=["flat", "cfg", "both"],
        default="both",
        help="flat: properties and blocks; cfg: every dimension from a nested YAML config",
    )
    args = parser.parse_args()
    shapes = {"flat": [False], "cfg": [True], "both": [False, True]}[args.shape]

    with tempfile.TemporaryDirectory() as tmp:
        directory = Path(tmp)
        print(
            f"{'robot':>14} {'links':>6} {'xacro 2.1.1 CPU':>16} {'belvedere CPU':>14} "
            f"{'ratio':>7}  identical"
        )
        ratios: dict[str, list[float]] = {}
        for nested, arms in ((n, a) for n in shapes for a in args.arms):
            robot = write_robot(directory, arms, args.segments, nested=nested)
            kind = "cfg" if nested else "flat"
            ref_cpu, _, ref = run(REFERENCE, robot)
            our_cpu, _, ours = run(OURS, robot)
            if ours.returncode != 0:
                print(ours.stderr, file=sys.stderr)
                return 1
            same = ref.returncode == 0 and ref.stdout == ours.stdout
            links = ours.stdout.count("<link ")
            ratio = ref_cpu / our_cpu
            ratios.setdefault(kind, []).append(ratio)
            print(
                f"{kind:>4} {arms:>4}x{args.segments:<3} {links:>6} {ref_cpu:>15.2f}s "
                f"{our_cpu:>13.2f}s {ratio:>6.1f}x  {'yes' if same else 'NO'}"
            )
            if not same:
                print(ref.stderr[-2000:], file=sys.stderr)
                return 1

        deep = write_robot(directory, 1, 300)
        ref_cpu, _, ref = run(REFERENCE, deep)
        our_cpu, _, ours = run(OURS, deep)
        ref_says = "ok" if ref.returncode == 0 else "fails: " + _last_error(ref.stderr)
        print(
            f"\n1x300 nesting: belvedere {our_cpu:.2f}s "
            f"({ours.stdout.count('<link ')} links); xacro 2.1.1 {ref_says}"
        )
        for kind, found in ratios.items():
            target = 15 if kind == "cfg" else 10
            print(
                f"speed-up ({kind}): {min(found):.1f}x to {max(found):.1f}x (target >= {target}x)"
            )
    return 0


def _last_error(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if "error" in line.lower()]
    return (lines[-1] if lines else stderr.strip().splitlines()[-1])[:100]


if __name__ == "__main__":
    sys.exit(main())
