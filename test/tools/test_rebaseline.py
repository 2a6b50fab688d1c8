#!/usr/bin/python3
"""scripts/rebaseline_eval keeps the acceptance floors: every eval test states some; a measurement
that fails one is refused (nothing rewritten, exit status 1); re-pinning rewrites the golden pins
only, never a floor or a comment. No replay: the script's rostest run is replaced by a table.

Registered in CMakeLists.txt with catkin_run_tests_target; run alone:
  /usr/bin/python3 test/tools/test_rebaseline.py
"""
import importlib.machinery
import importlib.util
import os
import pathlib
import re
import shutil
import sys
import tempfile
import unittest
import unittest.mock

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


def load_script():
    loader = importlib.machinery.SourceFileLoader("rebaseline_eval", str(ROOT / "scripts" / "rebaseline_eval"))
    spec = importlib.util.spec_from_loader("rebaseline_eval", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def table(tp, fp, fn, caught, episodes, lead_min, duty, truth_duty, detection=95.0):
    """The lines of test_eval_scenario's printed table that the script reads."""
    return (f"danger per object-frame: TP {tp} FP {fp} FN {fn} TN 100 (false alarms without a true object: 0)\n"
            f"precision 90.00 %  recall 90.00 %  accuracy 90.00 %\n"
            f"danger episodes: {caught} caught of {episodes}; warning lead time p50 {lead_min:.2f} s, min {lead_min:.2f} s\n"
            f"detection: recall {detection:.2f} %  precision 50.00 % (BEV centre to true footprint)\n"
            f"lamp duty cycle {duty:.1f} % (a perfect danger detector: {truth_duty:.1f} %)\n")


TEST = """<!-- A scenario's regression test. -->
<launch>
  <test test-name="eval_x" pkg="icanc" type="test_eval_scenario" time-limit="240">
    <param name="min_danger_tp" value="9"/>
    <param name="max_duty_cycle" value="0.3"/>
    <param name="accept/min_caught_fraction" value="1.0"/>
    <param name="accept/min_danger_recall" value="0.8"/>
    <param name="accept/min_lead_time_s" value="1.0"/>
    <param name="accept/max_duty_over_truth" value="0.15"/>
    <param name="scenario" value="x.yaml"/>
  </test>
</launch>
"""


class TestRebaseline(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.script = load_script()

    def setUp(self):
        self.tmp = pathlib.Path(tempfile.mkdtemp(prefix="icanc_rebaseline_"))
        self.test = self.tmp / "x.test"
        self.test.write_text(TEST)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def run_script(self, out):
        """The script's main() on self.test, its rostest run answering `out`; its exit code."""
        s = self.script
        s.EVAL = self.tmp
        answer = lambda *a, **k: type("Run", (), {"stdout": out})()
        with unittest.mock.patch.object(s.subprocess, "run", answer), \
                unittest.mock.patch.object(sys, "argv", ["rebaseline_eval", self.test.name]):
            try:
                s.main()
            except SystemExit as e:
                return e.code
        return 0

    def test_every_eval_test_states_floors(self):
        tests = sorted((ROOT / "test" / "rostest" / "eval").glob("*.test"))
        self.assertGreater(len(tests), 0)
        for test in tests:
            floors = re.findall(r'<param name="accept/([a-z_]+)"', test.read_text())
            self.assertTrue(floors, f"{test.name} states no acceptance floor (accept/*)")
            unknown = set("accept/" + f for f in floors) - set(self.script.measured_for_floors(
                self.script_table_match(table(1, 0, 0, 1, 1, 1.0, 10, 5))))
            self.assertFalse(unknown, f"{test.name}: unknown floors {unknown}")

    def script_table_match(self, out):
        return {k: m.groups() for k, p in self.script.PATTERNS.items() for m in [re.search(p, out)] if m}

    def test_passing_measurement_repins_and_keeps_floors_and_comment(self):
        code = self.run_script(table(12, 1, 2, 1, 1, 1.5, 30.0, 20.0))
        self.assertEqual(code, 0)
        text = self.test.read_text()
        self.assertIn('<param name="min_danger_tp" value="11"/>', text)
        self.assertIn('<param name="max_danger_fn" value="3"/>', text)
        for line in TEST.splitlines():
            if "accept/" in line or "<!--" in line:
                self.assertIn(line, text)

    def test_lost_episode_is_refused(self):
        code = self.run_script(table(12, 1, 2, 0, 1, 0.0, 30.0, 20.0))
        self.assertEqual(code, 1)
        self.assertEqual(self.test.read_text(), TEST, "a refused test is not rewritten")

    def test_each_floor_refuses(self):
        cases = {
            "recall": table(7, 1, 3, 1, 1, 1.5, 30.0, 20.0),       # 0.70 < 0.8
            "lead": table(12, 1, 2, 1, 1, 0.4, 30.0, 20.0),        # 0.4 s < 1.0 s
            "duty": table(12, 1, 2, 1, 1, 1.5, 40.0, 20.0),        # 20 points over the truth's
        }
        for what, out in cases.items():
            with self.subTest(what):
                self.assertEqual(self.run_script(out), 1)
                self.assertEqual(self.test.read_text(), TEST)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import junit
    junit.main(TestRebaseline, "rebaseline")
