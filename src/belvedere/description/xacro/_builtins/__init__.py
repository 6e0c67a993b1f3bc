"""What expressions can reach: the values we make (YAML data, namespaces, lambdas, bound
methods), the functions they may call and the attributes they may read.

A value reaches Python's object model only through an attribute, a call or a format field;
all three are decided here, by type and by name, from explicit lists.

Its modules: the values (:mod:`._values`), the functions (:mod:`._functions`), the attributes
and methods (:mod:`._methods`).
"""

from belvedere.description.xacro._builtins._functions import call, math_functions, python_functions
from belvedere.description.xacro._builtins._methods import attribute
from belvedere.description.xacro._builtins._values import (
    MISSING,
    NO_KWARGS,
    Code,
    Frame,
    Lambda,
    Namespace,
    YamlDict,
    YamlList,
    expose,
    to_yaml_value,
)

__all__ = [
    "MISSING",
    "NO_KWARGS",
    "Code",
    "Frame",
    "Lambda",
    "Namespace",
    "YamlDict",
    "YamlList",
    "attribute",
    "call",
    "expose",
    "math_functions",
    "python_functions",
    "to_yaml_value",
]
