"""ROS's ``name:=value`` command-line arguments, as roslaunch, rosrun and xacro read them.

One home for the three readings, below every layer that uses them (xacro's command line,
the verbs' ``name:=value`` arguments, rosrun's ``_param:=`` and ``__name:=``):

- :func:`split_mappings`: roslaunch's and xacro's (``rosgraph.names.load_mappings``): every
  ``name:=value``, private ``_param:=value`` dropped.
- :func:`split_ros_args`: rosrun's: remaps, private parameters (YAML values), ``__name`` and
  ``__ns``, and the plain arguments.
"""

from __future__ import annotations

__all__ = ["split_mappings", "split_ros_args"]


def split_mappings(argv: list[str]) -> tuple[list[str], dict[str, str]]:
    """Separate ``name:=value`` arguments (ROS remappings) from the rest.

    Private-parameter assignments (``_name:=value``) are dropped, as rosgraph does.
    """
    rest: list[str] = []
    mappings: dict[str, str] = {}
    for arg in argv:
        if ":=" not in arg:
            rest.append(arg)
            continue
        src, _, dst = arg.partition(":=")
        src, dst = src.strip(), dst.strip()
        if not src:
            continue
        if len(src) > 1 and src[0] == "_" and src[1] != "_":
            continue
        mappings[src] = dst
    return rest, mappings


def split_ros_args(
    words: list[str],
) -> tuple[list[str], dict[str, str], dict[str, object], str | None, str | None]:
    """rosrun's arguments: (plain arguments, remaps, private parameters, __name, __ns)."""
    plain: list[str] = []
    remaps: dict[str, str] = {}
    params: dict[str, object] = {}
    name = namespace = None
    import yaml

    for word in words:
        key, sep, value = word.partition(":=")
        if not sep or not key:
            plain.append(word)
        elif key == "__name":
            name = value
        elif key == "__ns":
            namespace = value
        elif key.startswith("__"):
            continue  # __log:=, __ip:=, __hostname:=, __master:= mean nothing here
        elif key.startswith("_"):
            try:
                params[key[1:]] = yaml.safe_load(value) if value else ""
            except yaml.YAMLError:
                params[key[1:]] = value
        else:
            remaps[key] = value
    return plain, remaps, params, name, namespace
