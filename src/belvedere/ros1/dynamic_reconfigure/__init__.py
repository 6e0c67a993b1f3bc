"""dynamic_reconfigure for rospy scripts: :mod:`.server`'s ``Server``, :mod:`.client`'s
``Client``, the ``<pkg>.cfg.<Name>Config`` modules made from a package's ``.cfg`` files (run
sandboxed, :mod:`._cfgfile`), and ``dynparam`` (:mod:`.dynparam`).

:mod:`._description` holds what belvedere's own reconfigurable nodes share with them: the
parameters' description and the server's rules, free of rospy.
"""

from belvedere.ros1.dynamic_reconfigure._exceptions import (
    DynamicReconfigureCallbackException,
    DynamicReconfigureParameterException,
)

__all__ = [
    "DynamicReconfigureCallbackException",
    "DynamicReconfigureParameterException",
    "find_reconfigure_services",
    "get_parameter_names",
]


def find_reconfigure_services() -> list[str]:
    """The nodes that serve ``set_parameters``, sorted."""
    from belvedere.ros1.dynamic_reconfigure.dynparam import reconfigurable_nodes

    return reconfigurable_nodes()


def get_parameter_names(node: str) -> list[str]:
    """The parameter names node ``node`` describes (waits for its description)."""
    from belvedere.ros1.dynamic_reconfigure.client import Client

    described = Client(node).get_parameter_descriptions() or []
    return [p["name"] for p in described]
