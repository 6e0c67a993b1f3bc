"""Graphviz pictures as rqt_graph, view_frames/rqt_tf_tree and urdf_to_graphiz draw them: laid
out by ``dot``, written to files, or served live as a page on 127.0.0.1."""

from belvedere.pictures._dot import DotError, render, require_dot, write_pictures
from belvedere.pictures._frames import FramesWatch
from belvedere.pictures._graph_info import graph_info, publishers_of
from belvedere.pictures._page import Draw, PicturePage
from belvedere.pictures._rqt_graph import MODES, GraphView, graph_dot

__all__ = [
    "MODES",
    "DotError",
    "Draw",
    "FramesWatch",
    "GraphView",
    "PicturePage",
    "graph_dot",
    "graph_info",
    "publishers_of",
    "render",
    "require_dot",
    "write_pictures",
]
