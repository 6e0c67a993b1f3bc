"""Two rospy scripts that exercise actionlib, run as they are by Debian's ROS 1 and by
``belvedere run``: a server (a SimpleActionServer on ``move`` and a plain ActionServer on
``manual``) and a client that goes through success, abort, cancel, preemption by a newer goal,
rejection, recall, the cancel-all calls, feedback and a timed-out ``wait_for_server``.

Everything each script prints must be the same under both. Events that come on different
topics (a goal's start on ``status``, its feedback, its result) are put in order by a
hand-shake on ``/actionlib_test/ack``: the server waits for the client's acknowledgement of
the start and of each feedback before going on, so the lines printed do not depend on timing.
At the end the client says ``quit``, the server answers on ``/actionlib_test/bye`` and stops a
moment after the client has gone.
"""

from __future__ import annotations

SERVER = r"""
import threading
import time
import rospy
import actionlib
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseFeedback, MoveBaseResult
from std_msgs.msg import String

rospy.init_node("server")
acks = []
acked = threading.Condition()


quit = threading.Event()


def on_ack(msg):
    with acked:
        acks.append(msg.data)
        acked.notify_all()
    if msg.data == "quit":
        quit.set()


def wait_ack(text):
    with acked:
        if not acked.wait_for(lambda: text in acks, timeout=30.0):
            print("no ack:", text, flush=True)


def say(*words):
    print(*words, flush=True)


ready = rospy.Publisher("/actionlib_test/ready", String, queue_size=1, latch=True)
bye = rospy.Publisher("/actionlib_test/bye", String, queue_size=1, latch=True)
rospy.Subscriber("/actionlib_test/ack", String, on_ack, queue_size=100)


def execute(goal):
    # Each branch prints before it ends the goal: once ended, the client goes on at once.
    label = goal.target_pose.header.frame_id
    kind = int(goal.target_pose.pose.position.x)
    say("execute", label, kind, "active:", server.is_active())
    if kind == 1:  # three feedbacks, then success
        wait_ack("active " + label)
        for k in range(1, 4):
            feedback = MoveBaseFeedback()
            feedback.base_position.header.frame_id = label
            feedback.base_position.pose.position.x = 0.1 * k
            server.publish_feedback(feedback)
            wait_ack("feedback %s %d" % (label, k))
        say("succeed", label)
        server.set_succeeded(MoveBaseResult(), "arrived at " + label)
    elif kind == 2:
        say("abort", label)
        server.set_aborted(text="blocked on the way to " + label)
    elif kind == 3:  # runs until asked to stop
        rate = rospy.Rate(50)
        while not server.is_preempt_requested():
            rate.sleep()
        say("preempt requested", label, "new goal:", server.is_new_goal_available())
        server.set_preempted(text="stopped " + label)
    elif kind == 4:  # returns without ending the goal: the server aborts it
        say("return", label)
    elif kind == 5:
        say("raise", label)
        raise ValueError("bad goal " + label)


rospy.set_param("move/status_frequency", 10.0)  # the deprecated name: a warning
rospy.set_param("manual/status_list_timeout", 600.0)  # ended goals stay listed
server = actionlib.SimpleActionServer("move", MoveBaseAction, execute, auto_start=False)
server.start()


def poll_goal():
    goal = poll.accept_new_goal()
    label = goal.target_pose.header.frame_id
    say("poll goal", label, "active:", poll.is_active(), "preempt:", poll.is_preempt_requested())
    if goal.target_pose.pose.position.x == 1:
        poll.set_succeeded(text="polled " + label)
    # else: runs until preempted


def poll_preempt():
    say("poll preempt", "active:", poll.is_active())
    poll.set_preempted(text="poll stopped")


poll = actionlib.SimpleActionServer("poll", MoveBaseAction)  # auto_start: a warning
poll.register_goal_callback(poll_goal)
poll.register_preempt_callback(poll_preempt)

handles = {}


def goal_cb(handle):
    goal = handle.get_goal()
    label = goal.target_pose.header.frame_id
    kind = int(goal.target_pose.pose.position.x)
    gid = handle.get_goal_id()
    say("manual goal", label, kind, "status", handle.get_goal_status().status,
        "id stamped:", gid.stamp.to_sec() > 0, "same handle:", handle == handle)
    handles[label] = handle
    if kind == 6:
        handle.set_rejected(MoveBaseResult(), "rejected " + label)
    elif kind == 7:
        handle.set_accepted("accepted " + label)
        handle.set_succeeded(text="done " + label)
        handle.set_succeeded(text="twice")  # an error: the goal is over
    elif kind == 9:  # feedback from a thread of its own, then success
        handle.set_accepted("accepted " + label)
        threading.Thread(target=finish, args=(handle, label)).start()
    # kind 8: left pending until canceled


def finish(handle, label):
    feedback = MoveBaseFeedback()
    feedback.base_position.header.frame_id = label
    feedback.base_position.pose.position.x = 0.5
    handle.publish_feedback(feedback)
    wait_ack("feedback %s 1" % label)
    say("manual succeed", label)
    handle.set_succeeded(text="done " + label)


def cancel_cb(handle):
    label = handle.get_goal().target_pose.header.frame_id
    say("manual cancel", label, "status", handle.get_goal_status().status)
    handle.set_canceled(text="recalled " + label)


manual = actionlib.ActionServer("manual", MoveBaseAction, goal_cb, cancel_cb, auto_start=False)
manual.start()
ready.publish(String("up"))
say("server up")
while not quit.wait(0.1) and not rospy.is_shutdown():
    pass
# The client leaves first: it waits for this, then ends.
bye.publish(String("bye"))
time.sleep(1.0)
rospy.signal_shutdown("the client is done")
say("server down")
"""

CLIENT = r'''
import re
import sys
import threading
import rospy
import actionlib
from actionlib import CommState, SimpleGoalState
import actionlib.msg
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from move_base_msgs.msg import MoveBaseAction, MoveBaseActionResult, MoveBaseGoal
from std_msgs.msg import String

NAMES = {getattr(GoalStatus, n): n for n in
         ("PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING",
          "RECALLING", "RECALLED", "LOST")}
COMM = {getattr(CommState, n): n for n in
        ("WAITING_FOR_GOAL_ACK", "PENDING", "ACTIVE", "WAITING_FOR_RESULT",
         "WAITING_FOR_CANCEL_ACK", "RECALLING", "PREEMPTING", "DONE", "LOST")}

# actionlib's send_goal follows a goal only after sending it: a callback thread that runs in
# between loses the goal's first transitions. Let this thread run on until it waits.
sys.setswitchinterval(1.0)
rospy.init_node("client")
ack = rospy.Publisher("/actionlib_test/ack", String, queue_size=100)
bye = threading.Event()
rospy.Subscriber("/actionlib_test/bye", String, lambda msg: bye.set())
rospy.wait_for_message("/actionlib_test/ready", String, timeout=60)
while ack.get_num_connections() == 0:
    rospy.sleep(0.01)


def say(*words):
    print(*words, flush=True)


def goal(label, kind):
    g = MoveBaseGoal()
    g.target_pose.header.frame_id = label
    g.target_pose.pose.position.x = float(kind)
    g.target_pose.pose.orientation.w = 1.0
    return g


class Tracker:
    """Records one goal's callbacks; the main thread prints them once the goal is done."""

    def __init__(self, label, client):
        self.label, self.client, self.events = label, client, []
        self.started = threading.Event()

    def active(self):
        self.events.append("active")
        self.started.set()
        ack.publish(String("active " + self.label))

    def feedback(self, fb):
        k = len([e for e in self.events if e.startswith("feedback")]) + 1
        self.events.append("feedback %s %.1f" % (fb.base_position.header.frame_id,
                                                 fb.base_position.pose.position.x))
        ack.publish(String("feedback %s %d" % (self.label, k)))

    def done(self, state, result):
        self.events.append("done %s %s" % (NAMES[state], type(result).__name__))

    def send(self, kind):
        self.client.send_goal(goal(self.label, kind), self.done, self.active, self.feedback)

    def report(self):
        say(self.label, "events:", "; ".join(self.events))
        say(self.label, "state:", NAMES[self.client.get_state()],
            "text:", repr(self.client.get_goal_status_text()))


nobody = actionlib.SimpleActionClient("nobody", MoveBaseAction)
say("wait nobody:", nobody.wait_for_server(rospy.Duration(0.5)))
say("no goal: state", NAMES[nobody.get_state()], "result", nobody.get_result(),
    "wait", nobody.wait_for_result(rospy.Duration(0.1)))

client = actionlib.SimpleActionClient("move", MoveBaseAction)
results = {}
ended = threading.Condition()


def on_result(msg):
    with ended:
        results[msg.status.goal_id.id] = msg.status
        ended.notify_all()


rospy.Subscriber("/move/result", MoveBaseActionResult, on_result, queue_size=100)
say("wait move:", client.wait_for_server(rospy.Duration(30)))

# success with feedback
t = Tracker("g1", client)
t.send(1)
say("g1 finished:", client.wait_for_result(rospy.Duration(30)))
t.report()
say("g1 id ok:", bool(re.match(r"^/client-\d+-\d+\.\d{3}$",
                               client.gh.comm_state_machine.action_goal.goal_id.id)))

# abort
t = Tracker("g2", client)
t.send(2)
client.wait_for_result(rospy.Duration(30))
t.report()

# cancel once active
t = Tracker("g3", client)
t.send(3)
t.started.wait(30)
client.cancel_goal()
client.wait_for_result(rospy.Duration(30))
t.report()

# preempted by a newer goal from another client
other = actionlib.SimpleActionClient("move", MoveBaseAction)
other.wait_for_server(rospy.Duration(30))
first = Tracker("g4", client)
first.send(3)
first.started.wait(30)
second = Tracker("g5", other)
second.send(1)
client.wait_for_result(rospy.Duration(30))
other.wait_for_result(rospy.Duration(30))
first.report()
second.report()

# an execute callback that ends without a result, one that raises
for label, kind in (("g6", 4), ("g7", 5)):
    t = Tracker(label, client)
    t.send(kind)
    client.wait_for_result(rospy.Duration(30))
    t.report()

# send_goal_and_wait past its execute timeout: canceled, then preempted
state = client.send_goal_and_wait(goal("g8", 3), rospy.Duration(1.0), rospy.Duration(30))
say("g8 send_goal_and_wait:", NAMES[state], repr(client.get_goal_status_text()))

# stop_tracking_goal: nothing is followed any more; cancel_all_goals still ends the goal
started = threading.Event()
client.send_goal(goal("g9", 3), active_cb=started.set)
started.wait(30)
gid = client.gh.comm_state_machine.action_goal.goal_id.id
client.stop_tracking_goal()
say("g9 untracked: state", NAMES[client.get_state()],
    "wait", client.wait_for_result(rospy.Duration(0.1)))
client.cancel_all_goals()
with ended:
    ended.wait_for(lambda: gid in results, timeout=30)
say("g9 result:", NAMES[results[gid].status], repr(results[gid].text))

# a SimpleActionServer driven by goal and preempt callbacks
polled = actionlib.SimpleActionClient("poll", MoveBaseAction)
say("wait poll:", polled.wait_for_server(rospy.Duration(30)))
t = Tracker("p1", polled)
t.send(1)
polled.wait_for_result(rospy.Duration(30))
t.report()
t = Tracker("p2", polled)
t.send(2)
t.started.wait(30)
polled.cancel_goal()
polled.wait_for_result(rospy.Duration(30))
t.report()

# the plain ActionServer, through the plain ActionClient
manual = actionlib.ActionClient("manual", MoveBaseAction)
say("wait manual:", manual.wait_for_server(rospy.Duration(30)))
seen = {}
cond = threading.Condition()


def transitions(label):
    def cb(gh):
        with cond:
            seen.setdefault(label, []).append(COMM[gh.get_comm_state()])
            cond.notify_all()
    return cb


def wait_state(label, state):
    with cond:
        cond.wait_for(lambda: state in seen.get(label, []), timeout=30)


def show(label, gh):
    say(label, "comm:", " ".join(seen.get(label, [])))
    say(label, "terminal:", NAMES[gh.get_terminal_state()], "status:",
        NAMES[gh.get_goal_status()], "text:", repr(gh.get_goal_status_text()),
        "result:", type(gh.get_result()).__name__)


feedbacks = []


def on_feedback(gh, fb):
    label = fb.base_position.header.frame_id
    feedbacks.append("%s %.1f" % (label, fb.base_position.pose.position.x))
    ack.publish(String("feedback %s 1" % label))


handles = {}
for label, kind in (("m1", 6), ("m2", 7), ("m6", 9)):
    handles[label] = manual.send_goal(goal(label, kind), transitions(label), on_feedback)
    wait_state(label, "DONE")
    show(label, handles[label])
say("manual feedback:", feedbacks)

# a goal left pending, canceled by its handle: recalled
handles["m3"] = manual.send_goal(goal("m3", 8), transitions("m3"))
wait_state("m3", "PENDING")
handles["m3"].cancel()
wait_state("m3", "DONE")
show("m3", handles["m3"])

# cancel_goals_at_and_before_time, then cancel_all_goals
handles["m4"] = manual.send_goal(goal("m4", 8), transitions("m4"))
wait_state("m4", "PENDING")
rospy.sleep(0.05)
cut = rospy.Time.now()
rospy.sleep(0.05)
handles["m5"] = manual.send_goal(goal("m5", 8), transitions("m5"))
wait_state("m5", "PENDING")
manual.cancel_goals_at_and_before_time(cut)
wait_state("m4", "DONE")
show("m4", handles["m4"])
say("m5 still:", COMM[handles["m5"].get_comm_state()])
manual.cancel_all_goals()
wait_state("m5", "DONE")
show("m5", handles["m5"])
say("handles equal:", handles["m4"] == handles["m4"], handles["m4"] != handles["m5"])
say("names:", CommState.to_string(CommState.DONE), SimpleGoalState.to_string(2),
    GoalStatus.to_string(GoalStatus.RECALLED))

# ended goals stay listed (for status_list_timeout): wait for a list in which all have ended
statuses = []


def on_status(msg):
    with cond:
        statuses.append(msg)
        cond.notify_all()


def all_ended():
    return statuses and all(s.status in (GoalStatus.REJECTED, GoalStatus.SUCCEEDED,
                                         GoalStatus.RECALLED) for s in statuses[-1].status_list)


rospy.Subscriber("/manual/status", GoalStatusArray, on_status)
with cond:
    cond.wait_for(all_ended, timeout=30)
status = statuses[-1]
labels = {gh.comm_state_machine.action_goal.goal_id.id: label for label, gh in handles.items()}
say("manual status:", " ".join("%s=%s:%s" % (labels.get(s.goal_id.id, "?"), NAMES[s.status],
                                             s.text) for s in status.status_list))
say("same classes:", actionlib.GoalStatus is GoalStatus, actionlib.msg.TestAction._type)
say("client done")
ack.publish(String("quit"))
bye.wait(30)
'''
