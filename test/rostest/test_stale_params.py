#!/usr/bin/env python3
"""rostest (stale_params.test): parameters of an earlier launch do not outlive a relaunch.

A namespace holds what an earlier launch (or a rosparam set) left: light_controller/
watchdog_enabled false, a stamp-check value and a key no profile has. launch/icanc.launch is then
started into that namespace against this master: once its profile is loaded, the stale keys must
be gone, and the LightController must start without the 'watchdog_enabled is false' warning.
"""
import os
import subprocess
import sys
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'scripts'))
from launch_util import stop_group  # noqa: E402 (scripts/launch_util.py, found through the line above)

NS = '/stale_check'
STALE = {
    NS + '/light_controller/watchdog_enabled': False,
    NS + '/obstacle_detector/stamp_check/max_jump_s': 1e6,
    NS + '/left_over_from_an_earlier_launch': 1,
}


class StaleParams(unittest.TestCase):
    def setUp(self):
        self.lines = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber('/rosout', Log, self.on_log, queue_size=200)

    def on_log(self, msg):
        with self.lock:
            self.lines.append(msg.msg)

    def saw(self, text):
        with self.lock:
            return any(text in line for line in self.lines)

    def wait_for(self, predicate, timeout_s):
        end = time.time() + timeout_s
        while time.time() < end and not rospy.is_shutdown():
            if predicate():
                return True
            time.sleep(0.1)
        return predicate()

    def test_relaunch_clears_the_namespace(self):
        for key, value in STALE.items():
            rospy.set_param(key, value)
        launch = subprocess.Popen(
            ['roslaunch', 'icanc', 'icanc.launch', 'ns:=' + NS.strip('/'), 'points_topic:=/none'],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        try:
            self.assertTrue(self.wait_for(lambda: rospy.has_param(NS + '/light_controller/tau_s'), 60.0),
                            'the profile was never loaded')
            for key in STALE:
                self.assertFalse(rospy.has_param(key), key + ' survived the relaunch')
            self.assertTrue(self.wait_for(lambda: self.saw('LightController: tau'), 60.0),
                            'the LightController never started')
            time.sleep(1.0)
            self.assertFalse(self.saw('watchdog_enabled is false'),
                             'the LightController started without its watchdog')
        finally:
            stop_group(launch, 20.0)


if __name__ == '__main__':
    rospy.init_node('test_stale_params')
    rostest.rosrun('icanc', 'stale_params', StaleParams, sys.argv)
