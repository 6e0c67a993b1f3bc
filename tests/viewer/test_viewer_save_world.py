"""File > Save World As in the viewer of a physics simulation: the simulation's world, as it
is now, written through its ``/gazebo/save_world`` service."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import GazeboRos, PhysicsSimulation
from belvedere.viewer import Viewer, ViewerError
from belvedere.world import read_world
from tests.conftest import EXAMPLES, free_port
from tests.viewer.test_browser import (
    MBOT,
    browser_page,
)
from tests.waiting import wait_until

PACKAGES = PackageIndex([EXAMPLES])
PLAYGROUND = EXAMPLES / "mbot_gazebo/worlds/playground.world"


class Running:
    """The playground with the mbot in it, paced, in a viewer."""

    def __init__(self) -> None:
        self.world = read_world(PLAYGROUND, packages=PACKAGES)
        self.graph = Graph()
        self.sim = PhysicsSimulation(self.graph, self.world)
        GazeboRos(self.sim, packages=PACKAGES)
        model = RobotModel.from_path(MBOT)
        self.sim.spawn(model, name="mbot", pose=Pose((0.5, 0.0, 0.0)), packages=PACKAGES)
        self.viewer = Viewer(
            self.graph,
            model=model,
            port=free_port(),
            sim=self.sim,
            world=self.world,
            world_poses=self.sim.model_poses,
        )
        self.graph.start(rtf=1.0)

    def close(self) -> None:
        self.viewer.close()
        self.graph.shutdown()


def test_save_world_as_writes_the_running_world(tmp_path: Path) -> None:
    running = Running()
    try:
        running.sim.pause(True)
        wait_until(lambda: running.graph.executor.paused, what="the simulation to pause")
        written = running.viewer.save_world(tmp_path / "saved.world")
        poses = {n: running.sim.model_pose(n) for n in running.sim.model_names()}
        with pytest.raises(ViewerError) as err:
            running.viewer.save_world(tmp_path)
        assert err.value.describe() == (
            f"error: cannot write {tmp_path}: Is a directory; {tmp_path} is unchanged"
        )
        with pytest.raises(ViewerError, match=r"give the path of the \.world file"):
            running.viewer.save_world("  ")
    finally:
        running.close()
    assert written == tmp_path / "saved.world"
    saved = read_world(written, packages=PACKAGES)
    assert [m.name for m in saved.models] == [*(m.name for m in running.world.models), "mbot"]
    mbot = saved.model("mbot")
    assert mbot is not None
    assert [p.filename for p in mbot.plugins] == ["libgazebo_ros_diff_drive.so"]
    fresh = PhysicsSimulation(Graph(), saved)
    assert list(fresh.robots) == ["mbot"]  # it drives again
    for name, pose in poses.items():
        np.testing.assert_allclose(fresh.model_pose(name), pose, atol=1e-6, err_msg=name)


@pytest.mark.browser
def test_the_save_world_as_button(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # the World file box says saved.world: here
    running = Running()
    try:
        with browser_page(running.viewer.url) as page:
            page.get_by_text("File", exact=True).click()
            button = page.get_by_role("button", name="Save World As")
            note = running.viewer.world_note

            def pressed() -> bool:
                """A click the loaded browser dropped is made again (the note says when the
                viewer got one)."""
                button.click()
                try:
                    wait_until(lambda: note.content != "", what="the click", timeout=10.0)
                except AssertionError:
                    return False
                return True

            wait_until(pressed, what="the viewer to take the click", interval=0.5)
            saved = tmp_path / "saved.world"
            wait_until(saved.exists, what="saved.world to be written", detail=lambda: note.content)
            wait_until(
                lambda: running.viewer.world_note.content == f"Saved `{saved}`.",
                what="the viewer to say where it saved the world",
                detail=lambda: running.viewer.world_note.content,
            )
    finally:
        running.close()
    names = [m.name for m in read_world(saved, packages=PACKAGES).models]
    assert names == [*(m.name for m in running.world.models), "mbot"]
