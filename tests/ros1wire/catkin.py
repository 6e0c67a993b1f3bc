"""A catkin workspace with the course's C++ nodes (written here in the course's style),
built once with Debian's catkin_make and g++ and kept between runs (keyed by its sources).

``learning_topic``: ``velocity_publisher`` (turtle1/cmd_vel), ``person_publisher`` and
``person_subscriber`` (its own ``Person.msg``), ``talker`` and ``listener`` (std_msgs/String)
and ``add_server`` (std_srvs/SetBool)."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
from pathlib import Path

__all__ = ["PACKAGE", "SOURCES", "build_workspace", "missing_catkin"]

PACKAGE = "learning_topic"

PERSON_MSG = """\
string name
uint8  sex
uint8  age

uint8 unknown = 0
uint8 male    = 1
uint8 female  = 2
"""

PACKAGE_XML = """\
<?xml version="1.0"?>
<package format="2">
  <name>learning_topic</name>
  <version>0.0.0</version>
  <description>The course's topic examples, in C++</description>
  <maintainer email="learner@example.com">learner</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <depend>roscpp</depend>
  <depend>std_msgs</depend>
  <depend>std_srvs</depend>
  <depend>geometry_msgs</depend>
  <build_depend>message_generation</build_depend>
  <exec_depend>message_runtime</exec_depend>
</package>
"""

CMAKELISTS = """\
cmake_minimum_required(VERSION 3.0.2)
project(learning_topic)
find_package(catkin REQUIRED COMPONENTS roscpp std_msgs std_srvs geometry_msgs message_generation)
add_message_files(FILES Person.msg)
generate_messages(DEPENDENCIES std_msgs)
catkin_package(CATKIN_DEPENDS roscpp std_msgs geometry_msgs message_runtime)
include_directories(${catkin_INCLUDE_DIRS})
foreach(node velocity_publisher person_publisher person_subscriber talker listener flag_server)
  add_executable(${node} src/${node}.cpp)
  target_link_libraries(${node} ${catkin_LIBRARIES})
  add_dependencies(${node} ${PROJECT_NAME}_generate_messages_cpp)
endforeach()
"""

# Each node stops after ~count messages when given the private parameter, so tests end.
SOURCES: dict[str, str] = {
    "velocity_publisher.cpp": """\
#include <ros/ros.h>
#include <geometry_msgs/Twist.h>

int main(int argc, char **argv)
{
    ros::init(argc, argv, "velocity_publisher");
    ros::NodeHandle n;
    ros::NodeHandle pn("~");
    int count = 0;
    pn.param("count", count, 0);
    ros::Publisher turtle_vel_pub = n.advertise<geometry_msgs::Twist>("/turtle1/cmd_vel", 10);
    ros::Rate loop_rate(10);
    for (int sent = 0; ros::ok() && (count == 0 || sent < count); ++sent)
    {
        geometry_msgs::Twist vel_msg;
        vel_msg.linear.x = 0.5;
        vel_msg.angular.z = 0.2;
        turtle_vel_pub.publish(vel_msg);
        ROS_INFO("Publsh turtle velocity command[%0.2f m/s, %0.2f rad/s]",
                 vel_msg.linear.x, vel_msg.angular.z);
        loop_rate.sleep();
    }
    return 0;
}
""",
    "person_publisher.cpp": """\
#include <ros/ros.h>
#include "learning_topic/Person.h"

int main(int argc, char **argv)
{
    ros::init(argc, argv, "person_publisher");
    ros::NodeHandle n;
    ros::NodeHandle pn("~");
    int count = 0;
    pn.param("count", count, 0);
    ros::Publisher person_info_pub = n.advertise<learning_topic::Person>("/person_info", 10);
    while (ros::ok() && person_info_pub.getNumSubscribers() == 0)
        ros::Duration(0.05).sleep();
    ros::Duration(0.3).sleep();
    ros::Rate loop_rate(20);
    for (int sent = 0; ros::ok() && (count == 0 || sent < count); ++sent)
    {
        learning_topic::Person person_msg;
        person_msg.name = "Tom";
        person_msg.age  = 18 + sent;
        person_msg.sex  = learning_topic::Person::male;
        person_info_pub.publish(person_msg);
        ROS_INFO("Publish Person Info: name:%s  age:%d  sex:%d",
                 person_msg.name.c_str(), person_msg.age, person_msg.sex);
        loop_rate.sleep();
    }
    ros::Duration(0.5).sleep();
    return 0;
}
""",
    "person_subscriber.cpp": """\
#include <ros/ros.h>
#include <cstdio>
#include "learning_topic/Person.h"

static int heard = 0;
static int wanted = 0;

void personInfoCallback(const learning_topic::Person::ConstPtr& msg)
{
    printf("Subcribe Person Info: name:%s  age:%d  sex:%d\\n",
           msg->name.c_str(), msg->age, msg->sex);
    fflush(stdout);
    if (wanted && ++heard >= wanted)
        ros::shutdown();
}

int main(int argc, char **argv)
{
    ros::init(argc, argv, "person_subscriber");
    ros::NodeHandle n;
    ros::NodeHandle pn("~");
    pn.param("count", wanted, 0);
    ros::Subscriber person_info_sub = n.subscribe("/person_info", 10, personInfoCallback);
    ros::spin();
    return 0;
}
""",
    "talker.cpp": """\
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <sstream>

int main(int argc, char **argv)
{
    ros::init(argc, argv, "talker");
    ros::NodeHandle n;
    ros::NodeHandle pn("~");
    int count = 0;
    pn.param("count", count, 0);
    ros::Publisher chatter_pub = n.advertise<std_msgs::String>("chatter", 1000);
    while (ros::ok() && chatter_pub.getNumSubscribers() == 0)
        ros::Duration(0.05).sleep();
    ros::Duration(0.3).sleep();
    ros::Rate loop_rate(50);
    for (int sent = 0; ros::ok() && (count == 0 || sent < count); ++sent)
    {
        std_msgs::String msg;
        std::stringstream ss;
        ss << "hello world " << sent;
        msg.data = ss.str();
        chatter_pub.publish(msg);
        loop_rate.sleep();
    }
    ros::Duration(0.5).sleep();
    return 0;
}
""",
    "listener.cpp": """\
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <cstdio>

static int heard = 0;
static int wanted = 0;

void chatterCallback(const std_msgs::String::ConstPtr& msg)
{
    printf("I heard: [%s]\\n", msg->data.c_str());
    fflush(stdout);
    if (wanted && ++heard >= wanted)
        ros::shutdown();
}

int main(int argc, char **argv)
{
    ros::init(argc, argv, "listener");
    ros::NodeHandle n;
    ros::NodeHandle pn("~");
    pn.param("count", wanted, 0);
    ros::Subscriber sub = n.subscribe("chatter", 1000, chatterCallback);
    ros::spin();
    return 0;
}
""",
    "flag_server.cpp": """\
#include <ros/ros.h>
#include <std_srvs/SetBool.h>

bool setFlag(std_srvs::SetBool::Request &req, std_srvs::SetBool::Response &res)
{
    res.success = req.data;
    res.message = req.data ? "flag up" : "flag down";
    return true;
}

int main(int argc, char **argv)
{
    ros::init(argc, argv, "flag_server");
    ros::NodeHandle n;
    ros::ServiceServer service = n.advertiseService("/set_flag", setFlag);
    ros::spin();
    return 0;
}
""",
}

CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "belvedere-tests"


def missing_catkin() -> str | None:
    """Why the workspace cannot be built here, or None."""
    for tool in ("catkin_make", "g++", "cmake"):
        if shutil.which(tool, path="/usr/bin:" + os.environ.get("PATH", "")) is None:
            return f"{tool} is not installed (scripts/install.sh --dev installs it)"
    if not Path("/usr/include/ros/ros.h").exists():
        return "roscpp's headers are not installed (libroscpp-dev)"
    return None


def _write(src: Path) -> None:
    package = src / PACKAGE
    (package / "msg").mkdir(parents=True, exist_ok=True)
    (package / "src").mkdir(exist_ok=True)
    (package / "msg" / "Person.msg").write_text(PERSON_MSG)
    (package / "package.xml").write_text(PACKAGE_XML)
    (package / "CMakeLists.txt").write_text(CMAKELISTS)
    for name, text in SOURCES.items():
        (package / "src" / name).write_text(text)


def build_workspace() -> Path:
    """The built workspace (``<ws>/devel/lib/learning_topic/<node>``), built if needed."""
    digest = hashlib.sha256(
        "".join([PERSON_MSG, PACKAGE_XML, CMAKELISTS, *sorted(SOURCES.values())]).encode()
    ).hexdigest()[:16]
    workspace = CACHE / f"catkin_ws-{digest}"
    if (workspace / "devel" / "lib" / PACKAGE / "flag_server").exists():
        return workspace
    shutil.rmtree(workspace, ignore_errors=True)
    _write(workspace / "src")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_", "CMAKE"))}
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    env["PWD"] = str(workspace)  # catkin_make takes its workspace from $PWD
    build = subprocess.run(
        ["catkin_make", "-C", str(workspace), "-j2"],
        cwd=workspace,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    if build.returncode != 0:
        msg = f"catkin_make failed in {workspace}:\n{build.stdout[-3000:]}\n{build.stderr[-3000:]}"
        raise RuntimeError(msg)
    return workspace
