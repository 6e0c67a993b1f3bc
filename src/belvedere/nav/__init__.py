"""The algorithms of mapping and navigation, free of ROS plumbing: plain arrays in and out
(the nodes in :mod:`belvedere.nodes` wrap them with topics, parameters and TF)."""
