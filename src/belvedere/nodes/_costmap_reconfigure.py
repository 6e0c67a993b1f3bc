"""A costmap's dynamic_reconfigure servers, as costmap_2d's: ``~<costmap>/`` (Costmap2D.cfg's
rates and tolerance) and ``~<costmap>/<layer>/`` for each layer (its plugin's file). A layer's
new values take effect over the whole grid at the next update, as costmap_2d re-inflates after
a change."""

from __future__ import annotations

from typing import Any

from belvedere.nav.costmap._layers import InflationLayer, ObstacleLayer
from belvedere.nodes import _reconfigure as reconfigure
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.ros1.dynamic_reconfigure.graph_server import GraphServer

__all__ = ["serve_costmap"]


def serve_costmap(costmap: Costmap2DROS) -> None:
    """Serve the reconfiguration of ``costmap`` and of each of its layers."""
    node, name = costmap.node, costmap.name

    def own(config: dict[str, Any], level: int) -> None:
        costmap.params = reconfigure.replaced(costmap.params, config)
        if not costmap.stopped:  # the timers at the new rates
            costmap.stop()
            costmap.start()

    values = reconfigure.current(reconfigure.COSTMAP, costmap.params)
    GraphServer(node, reconfigure.COSTMAP, values, own, ns=f"~{name}")
    for layer_name, layer in costmap.costmap.layers:
        description = (
            reconfigure.INFLATION_LAYER
            if isinstance(layer, InflationLayer)
            else reconfigure.OBSTACLE_LAYER
            if isinstance(layer, ObstacleLayer)
            else reconfigure.GENERIC_LAYER
        )

        def apply(config: dict[str, Any], level: int, layer: Any = layer) -> None:
            layer.params = reconfigure.replaced(layer.params, config)
            costmap.costmap.rebuild_all()

        values = reconfigure.current(description, layer.params)
        GraphServer(node, description, values, apply, ns=f"~{name}/{layer_name}")
