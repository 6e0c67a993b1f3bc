"""URDF parse time: RobotModel against urdfdom's check_urdf, on the same 2000-link file.

Generates a 2000-link robot (20 arms x 100 links, each link with an inertial, a visual, a
collision; revolute joints with limits and dynamics; a transmission and a <gazebo> block
per joint), then times:

- belvedere: ``RobotModel.from_path`` in this process (best of 5, after one warm-up),
- belvedere ``check`` in a fresh process (start-up, parse, lint, tree printout),
- Debian's ``check_urdf`` (C++, urdfdom) in a fresh process (best of 5),

and prints the ratios. ``python benchmarks/urdf_parse.py [--links 2000]``
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from belvedere.description.urdf import RobotModel

LINK = """  <link name="{name}">
    <inertial><origin xyz="0 0 0.05"/><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.0005"/></inertial>
    <visual><origin xyz="0 0 0.05" rpy="0 0 0"/>
      <geometry><cylinder radius="0.02" length="0.1"/></geometry>
      <material name="grey"/></visual>
    <collision><origin xyz="0 0 0.05" rpy="0 0 0"/>
      <geometry><cylinder radius="0.02" length="0.1"/></geometry></collision>
  </link>
"""
JOINT = """  <joint name="{name}" type="revolute">
    <parent link="{parent}"/><child link="{child}"/>
    <origin xyz="0 0 0.1" rpy="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
    <dynamics damping="0.1" friction="0.01"/>
  </joint>
  <transmission name="{name}_trans">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="{name}">
      <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
    </joint>
    <actuator name="{name}_motor"><mechanicalReduction>1</mechanicalReduction></actuator>
  </transmission>
  <gazebo reference="{child}"><material>Gazebo/Grey</material><mu1>0.5</mu1></gazebo>
"""


def write_robot(path: Path, links: int) -> Path:
    arms = 20
    per_arm = max(1, (links - 1) // arms)
    parts = [
        '<?xml version="1.0"?>\n<robot name="bench">\n',
        '  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>\n',
        '  <link name="base_link"/>\n',
    ]
    for a in range(arms):
        parent = "base_link"
        for i in range(per_arm):
            name = f"arm{a}_link{i}"
            parts.append(LINK.format(name=name))
            parts.append(JOINT.format(name=f"arm{a}_joint{i}", parent=parent, child=name))
            parent = name
    parts.append("</robot>\n")
    path.write_text("".join(parts))
    return path


def best_of(n: int, fn: object) -> float:
    times = []
    for _ in range(n):
        start = time.perf_counter()
        fn()  # type: ignore[operator]
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, default=2001)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        urdf = write_robot(Path(tmp) / "bench.urdf", args.links)
        model = RobotModel.from_path(urdf)
        print(
            f"{len(model.links)} links, {len(model.joints)} joints, "
            f"{urdf.stat().st_size / 1e6:.1f} MB"
        )
        ours = best_of(5, lambda: RobotModel.from_path(urdf))
        print(f"belvedere RobotModel.from_path (in process): {ours * 1000:8.1f} ms")
        cli = best_of(
            3,
            lambda: subprocess.run(
                [sys.executable, "-m", "belvedere", "-q", "check", str(urdf)],
                capture_output=True,
                check=True,
            ),
        )
        print(f"belvedere check (fresh process):            {cli * 1000:8.1f} ms")
        tool = shutil.which("check_urdf")
        if tool is None:
            print("check_urdf not installed (Debian liburdfdom-tools): no reference")
            return 0
        ref = best_of(5, lambda: subprocess.run([tool, str(urdf)], capture_output=True, check=True))
        print(f"check_urdf (C++ urdfdom, fresh process):     {ref * 1000:8.1f} ms")
        print(
            f"\nratio check_urdf / belvedere parse: {ref / ours:.2f}x; "
            f"check_urdf / belvedere check: {ref / cli:.2f}x"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
