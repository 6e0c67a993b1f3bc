"""Reading SDF 1.4 to 1.9: ``.world`` files and ``model.sdf`` into a :class:`WorldModel`.

Handled: ``<physics>`` (and 1.4's gravity inside it), models (static or not) with links,
inertials, collisions, visuals, joints, nested models and frames; geometry box, cylinder,
sphere, plane, mesh, polyline; poses with ``degrees`` and quaternions, placed through each
scope's frame graph (:mod:`belvedere.world._frames`: SDF 1.7's ``relative_to``,
``attached_to``, ``canonical_link``, ``placement_frame``, ``expressed_in``; before 1.7 the
fixed rules and the ``frame`` attribute); ``<include>`` of ``model://`` (with ``<name>``,
``<pose>``, ``<static>``, ``<placement_frame>``); world ``<frame>``s; the ``<state>`` block
Gazebo writes when it saves a world; lights. What is not simulated (actors, populations,
heightmaps, world plugins) is a warning naming its line. A model's plugins and its links'
sensors are kept as written: a robot saved in the world runs them again.

The reader is one class over the element families: every family's poses, names and frames
(:mod:`._scope`), links and joints (:mod:`._links`), models and includes (:mod:`._models`),
physics, scene and lights (:mod:`._environment`), the world itself (:mod:`._read`).
"""

from belvedere.world._model import SDFError
from belvedere.world._sdf._read import empty_world, read_world, read_world_string

__all__ = ["SDFError", "empty_world", "read_world", "read_world_string"]
