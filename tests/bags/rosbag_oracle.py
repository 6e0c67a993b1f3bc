"""Run by Debian's /usr/bin/python3 (ROS 1's rosbag): ``read BAG`` prints the bag's messages
and connection headers as JSON; ``write BAG COMPRESSION`` writes a bag with rosbag's API.
Not imported by the tests themselves."""

import json
import sys

import rosbag
import rospy
from geometry_msgs.msg import PoseStamped, Twist
from std_msgs.msg import String


def fields(msg):
    if msg._type == "nav_msgs/Odometry":
        h = msg.header
        return {
            "seq": h.seq,
            "stamp": [h.stamp.secs, h.stamp.nsecs],
            "frame_id": h.frame_id,
            "child_frame_id": msg.child_frame_id,
            "x": msg.pose.pose.position.x,
            "y": msg.pose.pose.position.y,
            "wz": msg.twist.twist.angular.z,
        }
    if msg._type == "geometry_msgs/PoseStamped":
        h = msg.header
        return {"seq": h.seq, "stamp": [h.stamp.secs, h.stamp.nsecs], "x": msg.pose.position.x}
    if msg._type == "sensor_msgs/LaserScan":
        return {"seq": msg.header.seq, "frame_id": msg.header.frame_id, "ranges": list(msg.ranges)}
    if msg._type == "std_msgs/String":
        return {"data": msg.data}
    if msg._type == "geometry_msgs/Twist":
        return {"x": msg.linear.x, "wz": msg.angular.z}
    return {"type": msg._type}


def read(path):
    bag = rosbag.Bag(path)
    messages = [
        {"topic": topic, "t": t.to_nsec(), "type": msg._type, "fields": fields(msg)}
        for topic, msg, t in bag.read_messages()
    ]
    headers = [
        {k: v.decode() if isinstance(v, bytes) else v for k, v in c.header.items()}
        for c in sorted(bag._connections.values(), key=lambda c: c.id)
    ]
    bag.close()
    return {"messages": messages, "connections": headers}


def write(path, compression):
    bag = rosbag.Bag(path, "w", compression=compression)
    latched = {
        "topic": "/map_name",
        "type": String._type,
        "md5sum": String._md5sum,
        "message_definition": String._full_text,
        "callerid": "/map_server",
        "latching": "1",
    }
    bag.write(
        "/map_name",
        String(data="cloister"),
        rospy.Time(1699999999, 995000000),
        connection_header=latched,
    )
    for i in range(50):
        pose = PoseStamped()
        pose.header.seq = i
        pose.header.stamp = rospy.Time(1700000000, i * 20000000)
        pose.header.frame_id = "map"
        pose.pose.position.x = i * 0.5
        bag.write("/pose", pose, rospy.Time(1700000000, i * 20000000))
        if i % 10 == 0:
            cmd = Twist()
            cmd.linear.x = 0.1 * i
            bag.write("/cmd_vel", cmd, rospy.Time(1700000000, i * 20000000 + 1))
    bag.close()


if __name__ == "__main__":
    if sys.argv[1] == "read":
        json.dump(read(sys.argv[2]), sys.stdout)
    else:
        write(sys.argv[2], sys.argv[3])
