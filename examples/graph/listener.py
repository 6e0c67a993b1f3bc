"""A listener: prints what arrives on /chatter (from this process or any other), as a ROS
node logs it (``[INFO] [time]: I heard: …``, also on /rosout: see ``belvedere log``)."""

from belvedere.graph import Graph, ZenohTransport

graph = Graph(sim_time=False, transport=ZenohTransport())
node = graph.create_node("listener")
node.subscribe("chatter", "std_msgs/String", lambda msg: node.logger.info("I heard: %s", msg.data))
try:
    graph.run()
except KeyboardInterrupt:
    graph.shutdown()
