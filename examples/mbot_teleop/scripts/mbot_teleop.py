#!/usr/bin/env python
# -*- coding: utf-8 -*-
# A keyboard teleop in the course's style: Python 2, termios raw keys, /cmd_vel Twist.
import rospy
from geometry_msgs.msg import Twist
import sys, select, termios, tty

banner = """
Drive the robot:
   u    i    o
   j    k    l
   m    ,    .
q/z : faster/slower    CTRL-C to quit
"""

moves = {
    'i': (1, 0), 'o': (1, -1), 'j': (0, 1), 'l': (0, -1),
    'u': (1, 1), ',': (-1, 0), '.': (-1, 1), 'm': (-1, -1),
}
speeds = {'q': (1.1, 1.1), 'z': (0.9, 0.9)}


def get_key():
    tty.setraw(sys.stdin.fileno())
    ready, _, _ = select.select([sys.stdin], [], [], 0.1)
    if ready:
        key = sys.stdin.read(1)
    else:
        key = ''
    termios.tcsetattr(sys.stdin, termios.TCSADRAIN, settings)
    return key


def vels(speed, turn):
    return "currently:\tspeed %s\tturn %s " % (speed, turn)


if __name__ == "__main__":
    settings = termios.tcgetattr(sys.stdin)
    rospy.init_node('mbot_teleop')
    pub = rospy.Publisher('/cmd_vel', Twist, queue_size=5)
    speed = rospy.get_param('~speed', 0.5)
    turn = rospy.get_param('~turn', 1.0)
    x = 0
    th = 0
    count = 0
    try:
        print banner
        print vels(speed, turn)
        while(1):
            key = get_key()
            if key in moves.keys():
                x = moves[key][0]
                th = moves[key][1]
                count = 0
            elif key in speeds.keys():
                speed = speed * speeds[key][0]
                turn = turn * speeds[key][1]
                print vels(speed, turn)
            elif key == ' ' or key == 'k':
                x = 0
                th = 0
            else:
                count = count + 1
                if count > 4:
                    x = 0
                    th = 0
                if (key == '\x03'):
                    break
            twist = Twist()
            twist.linear.x = x * speed
            twist.angular.z = th * turn
            pub.publish(twist)
    except Exception, e:
        print e
    finally:
        twist = Twist()
        pub.publish(twist)
        termios.tcsetattr(sys.stdin, termios.TCSADRAIN, settings)
