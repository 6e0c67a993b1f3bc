"""actionlib over the graph: goals, status, results, cancels and preemption."""

from __future__ import annotations

from typing import Any

from belvedere.graph import ActionClient, ActionServer, GoalHandle, GoalStatus, Graph

TYPE = "control_msgs/FollowJointTrajectory"


def _server(graph: Graph, finish_after: float) -> tuple[ActionServer, list[GoalHandle]]:
    """A server that succeeds each goal ``finish_after`` seconds after it starts, unless it
    is asked to stop first (checked every 0.1 s)."""
    node = graph.create_node("server")
    started: list[GoalHandle] = []

    def execute(handle: GoalHandle) -> None:
        started.append(handle)
        deadline = node.now_ns() + round(finish_after * 1e9)

        def tick() -> None:
            if handle.cancel_requested:
                handle.preempted(text="stopped")
                timer.cancel()
            elif node.now_ns() >= deadline:
                handle.publish_feedback({"joint_names": ["j"]})
                handle.succeed({"error_code": 0})
                timer.cancel()

        timer = node.timer(0.1, tick)

    return ActionServer(node, "/act", TYPE, execute), started


def _goal() -> dict[str, Any]:
    return {"trajectory": {"joint_names": ["j"]}}


def test_goal_succeeds_with_status_feedback_and_result() -> None:
    graph = Graph()
    _, started = _server(graph, 0.5)
    client = ActionClient(graph.create_node("client"), "/act", TYPE)
    statuses: list[Any] = []
    graph.create_node("watch").subscribe(
        "/act/status", "actionlib_msgs/GoalStatusArray", statuses.append
    )
    goal = client.send_goal(_goal())
    graph.run(duration=0.3)
    assert client.status[goal] is GoalStatus.ACTIVE
    graph.run(duration=0.5)
    assert client.status[goal] is GoalStatus.SUCCEEDED
    assert list(client.feedback[goal][0].joint_names) == ["j"]
    assert client.results[goal].status.goal_id.id == goal
    assert [h.id for h in started] == [goal]
    # Status at 5 Hz; a finished goal stays listed for 5 s, then goes.
    assert 3 <= len(statuses) <= 6
    graph.run(duration=6.0)
    assert statuses[-1].status_list == []


def test_newer_goal_preempts_and_pending_goals_are_recalled() -> None:
    graph = Graph()
    server, started = _server(graph, 1.0)
    client = ActionClient(graph.create_node("client"), "/act", TYPE)
    first = client.send_goal(_goal())
    graph.run(duration=0.2)
    second = client.send_goal(_goal())
    third = client.send_goal(_goal())  # replaces the second before it starts
    graph.run(duration=0.5)
    assert client.status[first] is GoalStatus.PREEMPTED
    assert client.status[second] is GoalStatus.RECALLED
    assert client.status[third] is GoalStatus.ACTIVE
    assert [h.id for h in started] == [first, third]
    client.cancel()  # empty id: everything
    graph.run(duration=0.3)
    assert client.status[third] is GoalStatus.PREEMPTED
    assert server.current is None


def test_cancel_by_id_leaves_others() -> None:
    graph = Graph()
    _, _ = _server(graph, 1.0)
    client = ActionClient(graph.create_node("client"), "/act", TYPE)
    goal = client.send_goal(_goal())
    graph.run(duration=0.2)
    client.cancel("someone-else")
    graph.run(duration=0.3)
    assert client.status[goal] is GoalStatus.ACTIVE
    client.cancel(goal)
    graph.run(duration=0.3)
    assert client.status[goal] is GoalStatus.PREEMPTED
