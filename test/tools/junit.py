"""Runs a unittest.TestCase class as catkin runs a gtest: verbose text on stdout and, given
--gtest_output=xml:PATH, a JUnit result file that scripts/test_results counts (<testcase>,
<failure>, <error>, <skipped>). The process exits 0 only when every case passed."""
import os
import sys
import time
import unittest
import xml.etree.ElementTree as ET


class _Result(unittest.TextTestResult):
    def startTest(self, test):
        super().startTest(test)
        self.__dict__.setdefault("ran", []).append(test.id())


def _write_xml(path, suite_name, case_class, result, seconds):
    suite = ET.Element("testsuite", name=suite_name, tests=str(result.testsRun),
                       failures=str(len(result.failures)), errors=str(len(result.errors)),
                       skipped=str(len(result.skipped)), time="%.1f" % seconds)
    outcome = {}
    for kind, items in (("failure", result.failures), ("error", result.errors)):
        for test, text in items:
            outcome[test.id()] = (kind, text)
    for test, why in result.skipped:
        outcome[test.id()] = ("skipped", why)
    ran = getattr(result, "ran", [])
    for test_id in ran + [i for i in outcome if i not in ran]:  # a failed setUpClass is a case too
        case = ET.SubElement(suite, "testcase", classname=case_class, name=test_id.rsplit(".", 1)[-1])
        if test_id in outcome:
            kind, text = outcome[test_id]
            ET.SubElement(case, kind, message=text.strip().splitlines()[-1][:200] if text.strip() else kind).text = text
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main(case, suite_name):
    """Runs every test of TestCase class `case`; exits with its outcome."""
    xml = [a[len("--gtest_output=xml:"):] for a in sys.argv[1:] if a.startswith("--gtest_output=xml:")]
    start = time.time()
    outcome = unittest.TextTestRunner(resultclass=_Result, verbosity=2, stream=sys.stdout).run(
        unittest.defaultTestLoader.loadTestsFromTestCase(case))
    if xml:
        _write_xml(xml[0], suite_name, case.__name__, outcome, time.time() - start)
    sys.exit(0 if outcome.wasSuccessful() else 1)
