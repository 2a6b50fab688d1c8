#!/usr/bin/python3
"""scripts/report on a short simulated drive: one replay of pedestrian_near_toward's bag, then the
report's content is checked against what the graph answered (OUT_DIR/record.bag, read here on its
own): the files are there, the episodes listed are the lamp's switches in the recorded light
states, and every object flagged in an episode's frames is in that episode's table. A headless
Chromium (Debian's chromium, when installed) screenshots index.html to show that it renders.

Registered in CMakeLists.txt with catkin_run_tests_target; run alone:
  /usr/bin/python3 test/tools/test_report.py   (with the build's devel/setup.bash sourced)
"""
import html.parser
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENARIO = os.path.join(ROOT, "config", "scenarios", "pedestrian_near_toward.yaml")


def devel():
    """The devel space this environment sources (CMAKE_PREFIX_PATH), else build/'s."""
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(":") + [os.path.join(ROOT, "build", "devel")]:
        if prefix and os.access(os.path.join(prefix, "lib", "icanc", "icanc_sim_bag"), os.X_OK):
            return prefix
    raise RuntimeError("no icanc tools: build first (scripts/build) and source devel/setup.bash")


def tool(name):
    return os.path.join(devel(), "lib", "icanc", name)


def report_env():
    """This environment with the devel space's Python packages (icanc.msg) first on PYTHONPATH:
    catkin's cached environment, which run_tests uses, names the folder only if it existed when
    CMake first ran, and on a fresh build it did not."""
    env = dict(os.environ)
    python = os.path.join(devel(), "lib", "python3", "dist-packages")
    env["PYTHONPATH"] = os.pathsep.join(p for p in [python, env.get("PYTHONPATH", "")] if p)
    return env


class Page(html.parser.HTMLParser):
    """Episodes of the summary table and the ids of each episode's flagged-object table."""

    def __init__(self):
        super().__init__()
        self.episodes = []  # (number, start_s, end_s)
        self.tables = {}    # episode -> set of ids
        self.images = []
        self._table = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr" and "data-episode" in a:
            self.episodes.append((int(a["data-episode"]), float(a["data-start"]), float(a["data-end"])))
        elif tag == "table" and a.get("class") == "flagged":
            self._table = int(a["data-episode"])
            self.tables[self._table] = set()
        elif tag == "tr" and "data-id" in a and self._table is not None:
            self.tables[self._table].add(int(a["data-id"]))
        elif tag == "img":
            self.images.append(a["src"])

    def handle_endtag(self, tag):
        if tag == "table":
            self._table = None


class TestReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="icanc_report_test.")
        cls.out = os.path.join(cls.tmp, "report")
        bag = os.path.join(cls.tmp, "drive.bag")
        subprocess.check_call([tool("icanc_sim_bag"), SCENARIO, bag], stdout=subprocess.DEVNULL)
        cls.result = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "report.py"), bag, cls.out,
                                  "--vehicle", "zebra"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 universal_newlines=True, timeout=600, env=report_env())
        print(cls.result.stdout[-3000:])
        cls.page = Page()
        index = os.path.join(cls.out, "index.html")
        if os.path.isfile(index):
            with open(index) as f:
                cls.page.feed(f.read())

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def recorded(self):
        if self.result.returncode != 0:
            self.fail(self.failure())
        import rosbag
        states, arrays = [], []
        with rosbag.Bag(os.path.join(self.out, "record.bag")) as bag:
            for topic, m, _ in bag.read_messages(topics=["/icanc/light_state", "/icanc/obstacles_danger"]):
                (states if topic == "/icanc/light_state" else arrays).append(m)
        states = sorted((s for s in states if s.input_stamp.to_nsec() > 0), key=lambda s: s.header.stamp.to_nsec())
        return states, arrays

    def failure(self):
        """Why scripts/report.py failed: its last line first (a summary shows a message's first
        lines), then the end of its output and of the graph's replay log."""
        lines = self.result.stdout.strip().splitlines() or ["(no output)"]
        text = "scripts/report.py exited %d: %s\n%s" % (self.result.returncode, lines[-1], "\n".join(lines[-40:]))
        log = os.path.join(self.out, "replay.log")
        if os.path.isfile(log):
            with open(log, errors="replace") as f:
                text += "\n--- replay.log:\n" + "".join(f.readlines()[-40:])
        return text

    def test_files(self):
        self.assertEqual(self.result.returncode, 0, self.failure())
        for name in ["index.html", "timeline.png", "record.bag", "eval.json", "rows.csv"] + self.page.images:
            path = os.path.join(self.out, name)
            self.assertTrue(os.path.isfile(path), name)
            if name.endswith(".png"):
                with open(path, "rb") as f:
                    self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", name)
        self.assertIn("timeline.png", self.page.images)
        self.assertTrue(any(i.startswith("ep001_first") for i in self.page.images), self.page.images)

    def test_episodes_are_the_lamp_switches(self):
        states, _ = self.recorded()
        ons, prev = [], False
        for s in states:
            if s.on and not prev:
                ons.append(s.header.stamp.to_sec())
            prev = s.on
        self.assertGreater(len(ons), 0, "the pedestrian walking up to the robot lights the lamp")
        self.assertEqual([k for k, _, _ in self.page.episodes], list(range(1, len(ons) + 1)))
        for (_, start, _), on in zip(self.page.episodes, ons):
            self.assertAlmostEqual(start, on, places=3)

    def test_every_flagged_object_is_in_its_episode_table(self):
        _, arrays = self.recorded()
        checked = 0
        for k, start, end in self.page.episodes:
            flagged = {o.id for a in arrays if start - 1e-4 <= a.header.stamp.to_sec() < end
                       for o in a.obstacles if o.dangerous}
            self.assertTrue(flagged <= self.page.tables.get(k, set()),
                            "episode %d: flagged %s, table %s" % (k, sorted(flagged), sorted(self.page.tables.get(k, []))))
            checked += len(flagged)
        self.assertGreater(checked, 0)

    def test_a_record_with_the_former_heading_in_degrees_is_refused(self):
        """A record.bag from before icanc/Obstacle carried heading in radians (heading_deg, in
        degrees): --render-only says so and stops, instead of drawing from a field it misreads."""
        _, arrays = self.recorded()
        import genpy.dynamic
        import rosbag
        text = type(arrays[0])._full_text  # today's definition, as this run's record.bag stores it
        old_text = text.replace("float32 heading ", "float32 heading_deg ")
        self.assertNotEqual(old_text, text)
        old = genpy.dynamic.generate_dynamic("icanc/ObstacleArray", old_text)
        out = os.path.join(self.tmp, "former")
        os.makedirs(out)
        array = old["icanc/ObstacleArray"]()
        array.obstacles = [old["icanc/Obstacle"](id=1, heading_deg=180.0)]
        with rosbag.Bag(os.path.join(out, "record.bag"), "w") as bag:
            bag.write("/icanc/obstacles_danger", array)
        run = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "report.py"),
                              os.path.join(self.tmp, "drive.bag"), out, "--vehicle", "zebra", "--render-only"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                             timeout=120, env=report_env())
        self.assertNotEqual(run.returncode, 0, run.stdout[-1500:])
        self.assertIn("heading_deg", run.stdout)
        self.assertIn("without --render-only", run.stdout)
        self.assertFalse(os.path.exists(os.path.join(out, "index.html")))

    def test_browser_renders_it(self):
        browser = shutil.which("chromium") or shutil.which("chromium-browser")
        if browser is None:
            print("test_report: chromium not installed, the screenshot of index.html is skipped")
            self.skipTest("chromium not installed: no screenshot of index.html (apt-get install chromium)")
        index = os.path.join(self.out, "index.html")
        if not os.path.isfile(index):
            self.fail("no index.html to render: " + self.failure())
        shot = os.path.join(self.tmp, "shot.png")
        # Its own profile directory (not the user's, which another Chromium may hold) and no
        # shared memory (a container's /dev/shm is small).
        run = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                              "--user-data-dir=" + os.path.join(self.tmp, "chromium"), "--hide-scrollbars",
                              "--window-size=1200,2400", "--screenshot=" + shot, "file://" + index],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=120)
        self.assertTrue(os.path.isfile(shot), "chromium wrote no screenshot (exit %d): %s"
                        % (run.returncode, run.stdout[-1500:]))
        import matplotlib.image
        img = matplotlib.image.imread(shot)
        self.assertGreater(img.shape[0], 1000)
        # The figures are drawn: the page is not blank (many distinct grey levels).
        self.assertGreater(img[..., :3].std(), 0.05)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import junit
    junit.main(TestReport, "report")
