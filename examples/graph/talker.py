"""A talker: publishes std_msgs/String on /chatter at 2 Hz, in wall time, on the shared graph.

Run it, then in other terminals: ``python examples/graph/listener.py`` and/or
``belvedere topic echo /chatter``; ``belvedere log`` shows what both log. Stop with Ctrl-C.
"""

from belvedere.graph import Graph, ZenohTransport

graph = Graph(sim_time=False, transport=ZenohTransport())
node = graph.create_node("talker")
chatter = node.publisher("chatter", "std_msgs/String")
count = 0


def say() -> None:
    global count
    count += 1
    chatter.publish_data({"data": f"hello world {count}"})
    node.logger.info("said hello world %d", count)


node.timer(0.5, say)
try:
    graph.run()  # the executor runs every callback and timer on this thread
except KeyboardInterrupt:
    graph.shutdown()
