"""move_base's parts under its node (:mod:`belvedere.nodes.move_base`): its parameters, what
it reads from TF and sends (:mod:`._io`), its control cycle and recoveries (:mod:`._cycle`)."""

from belvedere.nodes._move_base._cycle import Cycle, State, Trigger
from belvedere.nodes._move_base._io import Floats
from belvedere.nodes._move_base._params import MoveBaseParams

__all__ = ["Cycle", "Floats", "MoveBaseParams", "State", "Trigger"]
