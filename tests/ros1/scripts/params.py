#!/usr/bin/env python3
"""Parameters of every type, namespaces, defaults, missing keys, private ~ and _param:=."""

import rospy

rospy.init_node("param_demo")

rospy.set_param("/demo/int", 42)
rospy.set_param("/demo/float", 0.25)
rospy.set_param("/demo/bool", True)
rospy.set_param("/demo/str", "hello")
rospy.set_param("/demo/list", [1, 2.5, "three", False])
rospy.set_param("/demo/dict", {"a": 1, "b": {"c": "deep"}})
rospy.set_param("/demo/nested/level1/level2", "bottom")
rospy.set_param("relative_param", "in my namespace")
rospy.set_param("~private_param", 7)

for key in ("int", "float", "bool", "str", "list", "dict", "nested/level1/level2"):
    value = rospy.get_param("/demo/" + key)
    print(key, repr(value), type(value).__name__)
print("nested ns:", rospy.get_param("/demo/nested"))
print("dict member:", rospy.get_param("/demo/dict/b/c"))
print("relative:", rospy.get_param("relative_param"), rospy.get_param("/relative_param"))
print("private:", rospy.get_param("~private_param"), rospy.get_param("/param_demo/private_param"))
print(
    "from argv:",
    repr(rospy.get_param("~speed")),
    repr(rospy.get_param("~mode")),
    repr(rospy.get_param("~flag")),
    repr(rospy.get_param("~gains")),
)
print("default:", rospy.get_param("/demo/absent", "fallback"), rospy.get_param("~absent", 3))
try:
    rospy.get_param("/demo/absent")
except KeyError as err:
    print("KeyError:", err, repr(err))
print(
    "has:",
    rospy.has_param("/demo/int"),
    rospy.has_param("/demo/absent"),
    rospy.has_param("/demo/nested"),
    rospy.has_param("~speed"),
)
rospy.delete_param("/demo/str")
print("after delete:", rospy.has_param("/demo/str"))
try:
    rospy.delete_param("/demo/str")
except KeyError as err:
    print("delete missing KeyError:", err)
rospy.set_param("/search_me", "found at root")
print("search:", rospy.search_param("search_me"), rospy.search_param("not_anywhere"))
names = sorted(n for n in rospy.get_param_names() if n.startswith(("/demo", "/param_demo")))
print("names:", names)
try:
    rospy.set_param("/demo/big", 2**40)
    print("big:", rospy.get_param("/demo/big"))
except Exception as err:  # noqa
    print("big int:", type(err).__name__, err)
rospy.set_param("/demo/neg", -(2**31))
print("min int32:", rospy.get_param("/demo/neg"))
rospy.set_param("/demo/replace", {"x": 1})
rospy.set_param("/demo/replace", {"y": 2})
print("replace dict:", rospy.get_param("/demo/replace"))
rospy.set_param("/demo/empty_list", [])
rospy.set_param("/demo/empty_str", "")
print(
    "empties:", repr(rospy.get_param("/demo/empty_list")), repr(rospy.get_param("/demo/empty_str"))
)
print("cached:", rospy.get_param_cached("/demo/int"))
rospy.loginfo("params done")
