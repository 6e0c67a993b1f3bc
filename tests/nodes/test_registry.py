"""Every package whose nodes belvedere runs is a package ``$(find PKG)`` finds (as a ROS
install has it), so a launch file may name its directory."""

from __future__ import annotations

from pathlib import Path

from belvedere.launch import load_launch
from belvedere.nodes._registry import MODULES
from belvedere.packages import PackageIndex


def test_every_node_package_is_found() -> None:
    packages = PackageIndex([])
    for name in MODULES:
        assert (packages.find(name) / "package.xml").is_file(), name


def test_find_of_a_node_package_in_a_launch_file(tmp_path: Path) -> None:
    launch = tmp_path / "nav.launch"
    launch.write_text(
        "<launch>\n"
        '  <arg name="amcl_dir" value="$(find amcl)"/>\n'
        '  <param name="where" value="$(arg amcl_dir)"/>\n'
        "</launch>\n"
    )
    loaded = load_launch(launch, packages=PackageIndex([tmp_path]))
    where = loaded.params["/where"].value
    assert Path(str(where)).name == "amcl"
