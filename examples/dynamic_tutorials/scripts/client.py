#!/usr/bin/env python

import dynamic_reconfigure.client
import rospy


def callback(config):
    rospy.loginfo(
        "Config set to {int_param}, {double_param}, {str_param}, {bool_param}, {size}".format(
            **config
        )
    )


if __name__ == "__main__":
    rospy.init_node("dynamic_client")

    client = dynamic_reconfigure.client.Client(
        "dynamic_tutorials", timeout=30, config_callback=callback
    )

    r = rospy.Rate(0.1)
    x = 0
    b = False
    while not rospy.is_shutdown():
        x = x + 1
        if x > 10:
            x = 0
        b = not b
        client.update_configuration(
            {
                "int_param": x,
                "double_param": (1 / (x + 1)),
                "str_param": str(rospy.get_rostime()),
                "bool_param": b,
                "size": 1,
            }
        )
        r.sleep()
