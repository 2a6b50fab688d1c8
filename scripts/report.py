#!/usr/bin/python3
"""Drive report: why the lamp lit, as static PNG + HTML (docs/report.md).

Replays BAG through the icanc graph with launch/eval.launch (icanc_eval's lockstep replay on sim
time, the same frames the evaluator scores), records the graph's answers into OUT_DIR/record.bag
(obstacles with their danger flags, light states, lamp commands, the detector's non-ground points
thinned), then draws OUT_DIR/index.html: a timeline of the drive, a bird's-eye picture and a table
of the flagged objects per lamp-on episode, the summary figures and, with ground truth in the bag,
the evaluator's scores and what kept the lamp on. Run through scripts/report (it sources the
build's devel space).
"""

import argparse
import bisect
import html
import json
import math
import os
import subprocess
import sys
import tempfile
import time

from launch_util import free_port, stop_group

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OBSTACLES = "/icanc/obstacles_danger"
LIGHT = "/icanc/light_state"
LAMP = "/icanc/lamp_command"
POINTS = "/icanc/obstacle_detector/obstacle_points"
MAX_POINTS = 12000  # non-ground points kept per frame in record.bag (every n-th)
CAUSE_NAMES = ["true_danger", "model", "labelled_perception", "unlabelled_standing",
               "unlabelled_moving", "unscored"]
CAUSE_TEXT = {
    "true_danger": "a truly dangerous object (TP)",
    "model": "the danger model's own false alarm: flagged on its perfect track too",
    "labelled_perception": "perception: a labelled object, not dangerous, flagged on the graph's track only",
    "unlabelled_standing": "no labelled object, standing still over ground",
    "unlabelled_moving": "no labelled object, moving over ground (a ghost velocity or an unlabelled road user)",
    "unscored": "outside the scored range or view, too sparse, or its danger unknown to the labels",
}
REASONS = {0: "off", 1: "danger", 2: "sensor stale", 3: "daylight", 4: "sensor blind", 5: "fault"}
REASON_COLOUR = {1: "#f0a020", 2: "#c03030", 3: "#8080ff", 4: "#802080", 5: "#c03030"}


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="scripts/report",
        description="Replays BAG through the icanc graph (lockstep, sim time: launch/eval.launch) and "
                    "writes OUT_DIR/index.html, a drive report with PNG figures: the lamp over the whole "
                    "drive and, for every lamp-on episode, what was flagged and why.")
    p.add_argument("bag", help="bag with a sensor_msgs/PointCloud2 topic (and /tf_static; /ground_truth, "
                               "/tf or /odom when it has them)")
    p.add_argument("out_dir", help="directory for index.html, the PNGs, record.bag, eval.json, rows.csv")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--vehicle", default="zebra", help="profile in config/: zebra | carla_model3 | kitti_hdl64e (zebra)")
    g.add_argument("--profile", help="parameter file, any path (instead of --vehicle)")
    p.add_argument("--danger-model", default="profile", help="paper | predictive | profile: the profile's (profile)")
    p.add_argument("--points-topic", help="cloud topic (default /points, else the bag's only PointCloud2 topic)")
    p.add_argument("--ego-motion", default="auto",
                   help="tf | odometry | lidar | none | profile | auto: the profile's, or lidar when the profile "
                        "wants tf or odometry and the bag has none (auto)")
    p.add_argument("--fov", type=float, default=180.0,
                   help="half angle around +x scored against the ground truth [deg] (KITTI labels: 45)")
    p.add_argument("--render-only", action="store_true",
                   help="no replay: draw again from OUT_DIR/record.bag and eval.json of an earlier run")
    p.add_argument("--port", type=int, default=0, help="ROS master port for the replay (0: a free one)")
    return p.parse_args(argv)


# ----------------------------------------------------------------------------- inputs

def load_profile(args):
    import yaml
    path = args.profile or os.path.join(ROOT, "config", args.vehicle + ".yaml")
    if not os.path.isfile(path):
        sys.exit("report: no profile " + path)
    with open(path) as f:
        return os.path.abspath(path), yaml.safe_load(f) or {}


def get(d, *keys, default=None):
    for k in keys:
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d


def inspect_bag(path, points_topic):
    import rosbag
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info()
        topics = {t: (v.msg_type, v.message_count) for t, v in info.topics.items()}
        clouds = [t for t, (ty, _) in topics.items() if ty == "sensor_msgs/PointCloud2"]
        if points_topic is None:
            points_topic = "/points" if "/points" in clouds else (clouds[0] if len(clouds) == 1 else None)
        if points_topic is None or points_topic not in clouds:
            sys.exit("report: %s: no PointCloud2 topic %s (PointCloud2 topics: %s); give --points-topic"
                     % (path, points_topic or "/points", ", ".join(clouds) or "none"))
        static = []
        for _, m, _ in bag.read_messages(topics=["/tf_static"]):
            static.extend(m.transforms)
        truth = {}
        if topics.get("/ground_truth", ("",))[0] == "icanc/GroundTruthArray":
            for _, m, _ in bag.read_messages(topics=["/ground_truth"]):
                truth[m.header.stamp.to_nsec()] = m
        cloud_cls = None
        for _, m, _ in bag.read_messages(topics=[points_topic]):
            if m.fields:
                # The bag's own PointCloud2 and PointField classes (from the definition it stores):
                # the recorder needs no python3-sensor-msgs.
                cloud_cls = (type(m), type(m.fields[0]))
                break
        clouds_n = topics[points_topic][1]
        span = (bag.get_start_time(), bag.get_end_time())
    return {"topics": topics, "points_topic": points_topic, "static_tf": static, "truth": truth,
            "clouds": clouds_n, "span": span, "cloud_cls": cloud_cls}


# ----------------------------------------------------------------------------- replay

def thin_cloud(msg, classes):
    """The cloud's x, y, z as a new PointCloud2 of at most MAX_POINTS points (every n-th)."""
    import numpy as np
    PointCloud2, PointField = classes
    off = {f.name: f.offset for f in msg.fields}
    n = msg.width * msg.height
    out = PointCloud2()
    out.header = msg.header
    out.height = 1
    out.fields = [PointField(name=c, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                  for i, c in enumerate("xyz")]
    out.point_step = 12
    out.is_bigendian = False
    out.is_dense = True
    if n == 0 or not all(c in off for c in "xyz"):
        out.width = 0
        out.row_step = 0
        out.data = b""
        return out
    dt = np.dtype({"names": list("xyz"), "formats": ["<f4"] * 3,
                   "offsets": [off[c] for c in "xyz"], "itemsize": msg.point_step})
    pts = np.frombuffer(msg.data, dtype=dt, count=n)
    step = max(1, int(math.ceil(n / float(MAX_POINTS))))
    pts = pts[::step]
    xyz = np.empty((len(pts), 3), dtype="<f4")
    for i, c in enumerate("xyz"):
        xyz[:, i] = pts[c]
    xyz = xyz[np.isfinite(xyz).all(axis=1)]
    out.width = len(xyz)
    out.row_step = 12 * out.width
    out.data = xyz.tobytes()
    return out


def replay(args, bag_path, out, profile_path, profile, binfo):
    """Runs eval.launch on its own master with a recorder subscribed first; returns the ego source used."""
    topics = binfo["topics"]
    source = get(profile, "ego_motion", "source", default="none")
    if args.ego_motion == "auto":
        has_tf = "/tf" in topics
        has_odom = "/odom" in topics
        if (source == "tf" and not has_tf) or (source == "odometry" and not has_odom):
            print("report: the profile's ego_motion/source is %s but the bag has no %s: LiDAR odometry (lidar)"
                  % (source, "/tf" if source == "tf" else "/odom"), file=sys.stderr)
            source = "lidar"
    elif args.ego_motion != "profile":
        source = args.ego_motion
    model = args.danger_model
    if model in ("", "profile"):
        model = get(profile, "danger_detector", "model", default="paper")

    port = args.port or free_port()
    env = dict(os.environ)
    env["ROS_MASTER_URI"] = "http://localhost:%d" % port
    log_dir = tempfile.mkdtemp(prefix="ros_log.", dir=out)
    env["ROS_LOG_DIR"] = log_dir
    os.environ.update({"ROS_MASTER_URI": env["ROS_MASTER_URI"], "ROS_LOG_DIR": log_dir})
    log = open(os.path.join(out, "replay.log"), "w")
    core = subprocess.Popen(["roscore", "-p", str(port)], stdout=log, stderr=subprocess.STDOUT, env=env,
                            start_new_session=True)
    launch = None
    closers = []  # what the replay leaves open on an error (the record: closed, so it is readable)
    try:
        import rosgraph
        master = rosgraph.Master("/icanc_report")
        for _ in range(200):
            try:
                master.getPid()
                break
            except Exception:
                time.sleep(0.1)
        else:
            sys.exit("report: the ROS master on port %d did not come up (%s)" % (port, log.name))
        import rosbag
        import rospy
        from icanc.msg import LampCommand, LightState, ObstacleArray
        import threading
        lock = threading.Lock()
        record = rosbag.Bag(os.path.join(out, "record.bag"), "w")
        closers.append(lambda: record.close())
        seen = {"frames": 0, "lamp": None, "t": None}

        def write(topic, msg, stamp):
            t = stamp if stamp.to_nsec() > 0 else rospy.Time(0, 1)
            with lock:
                record.write(topic, msg, t)

        def on_array(m):
            write(OBSTACLES, m, m.header.stamp)
            seen["frames"] += 1
            seen["t"] = m.header.stamp.to_sec()

        def on_light(m):
            write(LIGHT, m, m.header.stamp)
            seen["lamp"] = m.on

        rospy.init_node("icanc_report", anonymous=True, disable_signals=True)
        subs = [rospy.Subscriber(OBSTACLES, ObstacleArray, on_array, queue_size=None),
                rospy.Subscriber(LIGHT, LightState, on_light, queue_size=None),
                rospy.Subscriber(LAMP, LampCommand, lambda m: write(LAMP, m, m.header.stamp), queue_size=None),
        ]
        if binfo["cloud_cls"] is not None:
            cls = binfo["cloud_cls"]
            subs.append(rospy.Subscriber(POINTS, cls[0], lambda m: write(POINTS, thin_cloud(m, cls), m.header.stamp),
                                         queue_size=None, buff_size=1 << 26))
        cmd = ["roslaunch", "--port", str(port), "icanc", "eval.launch", "bag:=" + bag_path,
               "profile:=" + profile_path, "points_topic:=" + binfo["points_topic"],
               "danger_model:=" + model, "ego_motion_source:=" + source, "fov_deg:=%g" % args.fov,
               "json:=" + os.path.join(out, "eval.json"), "rows:=" + os.path.join(out, "rows.csv")]
        launch = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        total = binfo["clouds"]
        t0, t1 = binfo["span"]
        tty = sys.stderr.isatty()
        last = 0.0
        while launch.poll() is None:
            time.sleep(0.2)
            now = time.time()
            if tty or now - last > 5.0:
                last = now
                lamp = {None: "-", True: "ON", False: "off"}[seen["lamp"]]
                line = "replaying %s: frame %d/%d, %.1f of %.1f s, lamp %s" % (
                    os.path.basename(bag_path), seen["frames"], total,
                    (seen["t"] - t0) if seen["t"] else 0.0, t1 - t0, lamp)
                print(("\r" + line + "   ") if tty else line, end="" if tty else "\n", file=sys.stderr, flush=True)
        if tty:
            print(file=sys.stderr)
        time.sleep(0.5)  # the last messages in flight
        for s in subs:
            s.unregister()
        with lock:
            closers.pop()()
        rospy.signal_shutdown("replay done")
    finally:
        for close in closers:
            close()
        for p in (launch, core):
            if p is not None and p.poll() is None:
                stop_group(p, 15)
        log.close()
        subprocess.call(["rm", "-rf", log_dir])
    print("report: replayed %d of %d frames (%s)" % (seen["frames"], total, os.path.join(out, "replay.log")),
          file=sys.stderr)
    with open(os.path.join(out, "replay.json"), "w") as f:
        json.dump({"ego_motion_source": source, "danger_model": model, "points_topic": binfo["points_topic"],
                   "profile": profile_path, "bag": bag_path}, f)


# ----------------------------------------------------------------------------- the record

class Frame(object):
    __slots__ = ("t", "stamp", "array", "obstacles", "points")


def recorded_with_heading_in_radians(array):
    """Whether an icanc/ObstacleArray read from a bag (its class generated from the definition the
    bag stores) has today's icanc/Obstacle heading [rad], not the former heading_deg [deg]."""
    import re
    return re.search(r"^\s*float32\s+heading\b", type(array)._full_text, re.M) is not None


def read_record(out):
    import rosbag
    frames, lights, lamps, points = {}, [], [], {}
    path = os.path.join(out, "record.bag")
    if not os.path.isfile(path):
        sys.exit("report: no %s (run without --render-only)" % path)
    with rosbag.Bag(path) as bag:
        for topic, m, _ in bag.read_messages():
            if topic == OBSTACLES and not frames and not recorded_with_heading_in_radians(m):
                sys.exit("report: %s was recorded by an older icanc (icanc/Obstacle heading_deg, in "
                         "degrees, now heading in radians): run again without --render-only" % path)
            if topic == OBSTACLES:
                frames[m.header.stamp.to_nsec()] = m
            elif topic == LIGHT:
                lights.append(m)
            elif topic == LAMP:
                lamps.append(m)
            elif topic == POINTS:
                points[m.header.stamp.to_nsec()] = m
    return frames, lights, lamps, points


def light_states(lights):
    """The light states from the first input on (input_stamp set), in stamp order."""
    states = [s for s in lights if s.input_stamp.to_nsec() > 0]
    states.sort(key=lambda s: s.header.stamp.to_nsec())  # stable: arrival order among equal stamps
    return states


def episodes_of(states, t_end_ns):
    """[(start_ns, end_ns, on_state, off_state or None)] of the lamp's on intervals."""
    eps, cur = [], None
    prev_on = False
    for s in states:
        if s.on and not prev_on:
            cur = [s.header.stamp.to_nsec(), None, s, None]
        elif not s.on and prev_on and cur is not None:
            cur[1], cur[3] = s.header.stamp.to_nsec(), s
            eps.append(tuple(cur))
            cur = None
        prev_on = s.on
    if cur is not None:
        cur[1] = max(t_end_ns, cur[0])
        eps.append(tuple(cur))
    return eps


def transforms(static_tf):
    """frame -> 4x4 root_T_frame over the bag's static transforms."""
    import numpy as np

    def mat(tr):
        q = tr.transform.rotation
        x, y, z, w = q.x, q.y, q.z, q.w
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        m = np.eye(4)
        m[:3, :3] = r
        v = tr.transform.translation
        m[:3, 3] = [v.x, v.y, v.z]
        return m
    parent = {t.child_frame_id.lstrip("/"): (t.header.frame_id.lstrip("/"), mat(t)) for t in static_tf}

    def root_T(frame, depth=0):
        if frame not in parent or depth > 32:
            return frame, np.eye(4)
        p, m = parent[frame]
        root, r = root_T(p, depth + 1)
        return root, r.dot(m)
    return root_T


def points_in(frame_msg, cloud, root_T):
    """The thinned cloud's x, y in the obstacles' frame (the bag's static transforms), or None."""
    import numpy as np
    if cloud is None or cloud.width == 0:
        return None
    xyz = np.frombuffer(cloud.data, dtype="<f4").reshape(-1, 3).astype(float)
    src, dst = cloud.header.frame_id.lstrip("/"), frame_msg.header.frame_id.lstrip("/")
    if src != dst:
        r1, a = root_T(src)
        r2, b = root_T(dst)
        if r1 != r2:
            return None  # frames not joined by the static transforms: not drawn
        m = np.linalg.inv(b).dot(a)
        xyz = xyz.dot(m[:3, :3].T) + m[:3, 3]
    return xyz[:, :2]


# ----------------------------------------------------------------------------- explanations

def motion_state_names(obstacle):
    """value -> name of the Obstacle message's motion_state constants (when it has the field)."""
    names = {}
    for k in dir(type(obstacle)):
        v = getattr(type(obstacle), k)
        if k.isupper() and isinstance(v, int) and not k.startswith("SECTION_") and (
                "MOTION" in k or "MOVING" in k or "STATIC" in k or "STANDING" in k or "UNKNOWN" in k):
            names[v] = k.replace("MOTION_STATE_", "").replace("MOTION_", "").lower()
    return names


def motion_state(o):
    if not hasattr(o, "motion_state"):
        return None
    return motion_state_names(o).get(o.motion_state, str(o.motion_state))


def ego_pose(vx, vy, w, t):
    """The vehicle's pose after t at body velocity (vx, vy) and yaw rate w, as icanc's
    predictEgoPose: (x, y, yaw)."""
    yaw = w * t
    if abs(yaw) < 1e-9:
        return vx * t, vy * t, yaw
    s, c = math.sin(yaw), math.cos(yaw)
    return (vx * s + vy * (c - 1.0)) / w, (vx * (1.0 - c) + vy * s) / w, yaw


def quads_overlap(a, b):
    """Separating axes of two convex quadrilaterals given as corner lists."""
    for poly in (a, b):
        for i in range(4):
            ex, ey = poly[(i + 1) % 4][0] - poly[i][0], poly[(i + 1) % 4][1] - poly[i][1]
            nx, ny = -ey, ex
            pa = [nx * x + ny * y for x, y in a]
            pb = [nx * x + ny * y for x, y in b]
            if max(pa) < min(pb) - 1e-9 or max(pb) < min(pa) - 1e-9:
                return False
    return True


def predicted_ttc(o, ego_twist, danger, with_uncertainty):
    """Seconds until the obstacle's axis-aligned box, moving at its velocity over ground (the static
    prior applied), overlaps the corridor seen from where the vehicle will be along its twist (0:
    now), or -1 within the reaction time: the predictive model's test on the box, without its
    footprint parts and the planner's path; the box grows by the velocity's uncertainty only when
    with_uncertainty (the model's own test; without it, the mean prediction)."""
    hw = danger["half_width"] + danger["margin"]
    length = danger["front"] + danger["stopping"]
    vx, vy, w = ego_twist.linear.x, ego_twist.linear.y, ego_twist.angular.z
    cx, cy = o.pose.position.x, o.pose.position.y
    sx, sy = max(0.0, o.velocity_std_axes.x), max(0.0, o.velocity_std_axes.y)
    gx = o.velocity.x + vx - w * cy
    gy = o.velocity.y + vy + w * cx

    def shrink(v, t):  # staticPriorShrink, the non-negative garrote
        return 0.0 if abs(v) <= t else v * (1.0 - t * t / (v * v))
    gx, gy = shrink(gx, danger["static_prior_k"] * sx), shrink(gy, danger["static_prior_k"] * sy)
    n = int(math.ceil(danger["reaction_time"] / danger["time_step"] - 1e-9))
    for i in range(n + 1):
        t = min(i * danger["time_step"], danger["reaction_time"])
        k = danger["velocity_std_k"] if with_uncertainty else 0.0
        grow_x = danger["footprint_margin"] + min(k * sx * t, danger["uncertainty_cap"])
        grow_y = danger["footprint_margin"] + min(k * sy * t, danger["uncertainty_cap"])
        ex, ey, yaw = ego_pose(vx, vy, w, t)
        c, s = math.cos(-yaw), math.sin(-yaw)
        box = []
        for x, y in ((o.aabb_min.x, o.aabb_min.y), (o.aabb_max.x, o.aabb_min.y),
                     (o.aabb_max.x, o.aabb_max.y), (o.aabb_min.x, o.aabb_max.y)):
            px, py = x + gx * t - ex, y + gy * t - ey
            box.append((c * px - s * py, s * px + c * py))
        corridor = [(-grow_x, -hw - grow_y), (length + grow_x, -hw - grow_y),
                    (length + grow_x, hw + grow_y), (-grow_x, hw + grow_y)]
        if quads_overlap(box, corridor):
            return t
    return -1.0


def why_flagged(o, arr, danger):
    section = {1: "left", 2: "front", 3: "right"}.get(o.section, "?")
    if danger["model"] == "predictive":
        t = predicted_ttc(o, arr.ego_twist, danger, False)
        if t == 0.0:
            return "in the corridor"
        if t > 0.0:
            return "predicted into the corridor in %.1f s (over ground %+.1f, %+.1f m/s)" % (
                t, o.velocity_over_ground.x, o.velocity_over_ground.y)
        t = predicted_ttc(o, arr.ego_twist, danger, True)
        if t >= 0.0:
            return "into the corridor in %.1f s only with its velocity's uncertainty (sigma %.2f, %.2f m/s)" % (
                t, o.velocity_std_axes.x, o.velocity_std_axes.y)
        return ("not into the corridor as its box predicts: its footprint parts or the planner's path, or "
                "held by the hysteresis (off after %d safe frames)" % danger["off_frames"])
    thr = o.speed * danger["reaction_time"]
    # The message's heading [rad, (-pi, pi]] as the paper's rule reads it: [0, 360) deg.
    return "%s section, closest %.1f m <= %.1f m/s x %.0f s = %.1f m, heading %.0f deg %s" % (
        section, o.closest_distance, o.speed, danger["reaction_time"], thr, math.degrees(o.heading) % 360.0,
        "toward" if o.moving_toward else "not toward")


def load_eval(path):
    """icanc_eval's JSON (its C++ stream writes nan / inf bare), or None."""
    import re
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        text = f.read()
    text = re.sub(r"(?<![\w.])-?nan(?![\w.])", "NaN", text)
    text = re.sub(r"(?<![\w.])(-?)inf(?![\w.])", r"\1Infinity", text)
    try:
        return json.loads(text)
    except ValueError as e:
        print("report: %s unreadable (%s): no evaluator figures" % (path, e), file=sys.stderr)
        return None


def read_rows(out):
    """(t_ms, det_id) -> cause of each flagged detection in eval's rows.csv."""
    import csv
    path = os.path.join(out, "rows.csv")
    causes = {}
    if not os.path.isfile(path):
        return causes
    with open(path) as f:
        for r in csv.DictReader(f):
            if r.get("det_dangerous") != "1" or not r.get("det_id"):
                continue
            key = (int(round(float(r["t"]) * 1000)), int(r["det_id"]))
            o = r["outcome"]
            if o == "TP":
                c = ("true_danger", "truth %s (%s)" % (r["truth_id"], r["truth_type"]))
            elif o == "SA":
                c = ("true_danger", "truth %s (%s), standing beside the swept path" % (r["truth_id"], r["truth_type"]))
            elif o == "DC":
                c = ("unscored", "truth %s (%s), not scored" % (r["truth_id"], r["truth_type"]))
            elif r.get("truth_id"):
                c = ("model" if r.get("perfect_dangerous") == "1" else "labelled_perception",
                     "truth %s (%s), not dangerous" % (r["truth_id"], r["truth_type"]))
            else:
                vg = math.hypot(float(r["det_vgx"] or 0), float(r["det_vgy"] or 0))
                c = ("unlabelled_standing" if vg < 0.5 else "unlabelled_moving", "no labelled object")
            causes[key] = c
    return causes


def perfect_lamp(frame_times_ns, truth, tau, recheck, end_ns):
    """The light controller on the truth's dangerous flags per frame: [(on_ns, off_ns)]."""
    out, end = [], None
    for t in frame_times_ns:
        g = truth.get(t)
        danger = g is not None and any(o.dangerous for o in g.objects)
        ts = t * 1e-9
        if end is not None and ts >= end - 1e-9:
            out[-1][1] = int(end * 1e9)
            end = None
        if danger and (end is None or end - ts <= recheck + 1e-9):
            if end is None:
                out.append([t, None])
            end = ts + tau
    if end is not None:
        out[-1][1] = int(end * 1e9)
    return [(a, min(b, end_ns)) for a, b in out]


def truth_intervals(frame_times_ns, truth, period_ns):
    """Spans of frames with a truly dangerous object."""
    spans = []
    for t in frame_times_ns:
        g = truth.get(t)
        if g is not None and any(o.dangerous for o in g.objects):
            if spans and t - spans[-1][1] <= 1.5 * period_ns:
                spans[-1][1] = t
            else:
                spans.append([t, t])
    return [(a, b + period_ns) for a, b in spans]


# ----------------------------------------------------------------------------- figures

def box_corners(o):
    c, s = math.cos(2 * math.atan2(o.pose.orientation.z, o.pose.orientation.w)), 0.0
    yaw = 2 * math.atan2(o.pose.orientation.z, o.pose.orientation.w)
    c, s = math.cos(yaw), math.sin(yaw)
    hl, hw = 0.5 * o.dimensions.x, 0.5 * o.dimensions.y
    pts = []
    for dx, dy in ((hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw)):
        pts.append((o.pose.position.x + c * dx - s * dy, o.pose.position.y + s * dx + c * dy))
    return pts


def draw_timeline(path, ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    t0 = ctx["t0"]
    rel = lambda ns: ns * 1e-9 - t0  # noqa: E731
    segments = ctx["segments"]
    rows = [("lamp", 2.2), ("flags", 1.6), ("motion", 1.6)]
    if segments:
        rows.insert(1, ("segments", 1.4))
    fig, axes = plt.subplots(len(rows), 1, sharex=True, figsize=(12, sum(h for _, h in rows) + 0.8),
                             gridspec_kw={"height_ratios": [h for _, h in rows]})
    ax = dict(zip([r for r, _ in rows], axes))
    a = ax["lamp"]
    lanes = ["lamp"]
    if ctx["truth"]:
        lanes = ["truly dangerous", "perfect detector's lamp", "lamp"]
    y = {name: i for i, name in enumerate(lanes)}
    for (s, e, on, _), k in zip(ctx["episodes"], range(1, len(ctx["episodes"]) + 1)):
        colour = REASON_COLOUR.get(on.reason, "#f0a020")
        a.broken_barh([(rel(s), max(rel(e) - rel(s), 0.02))], (y["lamp"] - 0.35, 0.7), color=colour)
        a.annotate("%d" % k, (rel(s), y["lamp"] + 0.38), fontsize=7, ha="left", va="bottom")
    if ctx["truth"]:
        a.broken_barh([(rel(s), rel(e) - rel(s)) for s, e in ctx["truth_spans"]],
                      (y["truly dangerous"] - 0.35, 0.7), color="#30a050")
        a.broken_barh([(rel(s), rel(e) - rel(s)) for s, e in ctx["perfect"]],
                      (y["perfect detector's lamp"] - 0.35, 0.7), color="#80c090")
        for lane, spans in (("truly dangerous", ctx["truth_spans"]), ("perfect detector's lamp", ctx["perfect"])):
            if not spans:
                a.text(0.1, y[lane], "none in the drive", fontsize=8, va="center", color="#555")
    a.set_yticks(range(len(lanes)))
    a.set_yticklabels(lanes)
    a.set_ylim(-0.6, len(lanes) - 0.2)
    handles = [matplotlib.patches.Patch(color=REASON_COLOUR[r], label="lamp on: " + REASONS[r])
               for r in sorted(set(on.reason for _, _, on, _ in ctx["episodes"]) & set(REASON_COLOUR))]
    if handles:
        a.legend(handles=handles, loc="upper right", fontsize=7, ncol=len(handles))
    a.set_title("lamp over the drive (numbers: the episodes below)", fontsize=9, loc="left")
    if segments:
        s = ax["segments"]
        if ctx["lamp_cmds"]:
            ts = [rel(c.header.stamp.to_nsec()) for c in ctx["lamp_cmds"]]
            n = len(segments)
            lv = np.array([list(c.levels)[:n] + [0.0] * (n - len(c.levels)) for c in ctx["lamp_cmds"]]).T
            s.pcolormesh(ts + [ts[-1] + 0.1], np.arange(n + 1) - 0.5, lv, vmin=0, vmax=1, cmap="YlOrBr",
                         shading="flat")
        s.set_ylabel("segment", fontsize=8)
        s.set_title("segment levels (0 off, 1 high beam; right to left)", fontsize=9, loc="left")
    f = ax["flags"]
    ft = [rel(t) for t in ctx["frame_ns"]]
    f.step(ft, [len(ctx["frames"][t].obstacles) for t in ctx["frame_ns"]], where="post", color="#9090a0",
           lw=0.8, label="tracked obstacles")
    f.step(ft, [sum(o.dangerous for o in ctx["frames"][t].obstacles) for t in ctx["frame_ns"]], where="post",
           color="#d02020", lw=1.2, label="flagged dangerous")
    f.set_ylabel("objects", fontsize=8)
    f.legend(loc="upper right", fontsize=7)
    m = ax["motion"]
    sp = [math.hypot(ctx["frames"][t].ego_twist.linear.x, ctx["frames"][t].ego_twist.linear.y) for t in ctx["frame_ns"]]
    yr = [math.degrees(ctx["frames"][t].ego_twist.angular.z) for t in ctx["frame_ns"]]
    m.plot(ft, sp, color="#2050c0", lw=1.0)
    m.set_ylabel("speed m/s", color="#2050c0", fontsize=8)
    m2 = m.twinx()
    m2.plot(ft, yr, color="#a04080", lw=0.8)
    m2.set_ylabel("yaw rate deg/s", color="#a04080", fontsize=8)
    m.set_title("vehicle's own motion (ego_motion source %s)" % ctx["ego_source"], fontsize=9, loc="left")
    m.set_xlabel("time since the first cloud [s]")
    m.set_xlim(0, max(ft[-1] if ft else 1.0, 0.1))
    for k in axes:
        k.grid(axis="x", alpha=0.3)
        k.tick_params(labelsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def draw_bev(path, ctx, t_ns, title, highlight):
    """Bird's-eye picture of one frame, forward up and left on the left (the driver's view from above)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import FancyArrowPatch, Polygon, Wedge
    arr = ctx["frames"][t_ns]
    d = ctx["danger"]
    roi_min, roi_max = ctx["roi"]
    # The region of interest, cut to what matters: 20 m ahead (10 m past the farthest flagged
    # object), 6 m behind (2 m past the rearmost) and 8 m to each side (4 m past the widest), at
    # most 45 m ahead and 20 m to each side.
    far = max([o.aabb_max.x for o in arr.obstacles if o.dangerous] + [10.0])
    wide = max([max(abs(o.aabb_min.y), abs(o.aabb_max.y)) for o in arr.obstacles if o.dangerous] + [4.0])
    near = min([o.aabb_min.x for o in arr.obstacles if o.dangerous] + [-4.0])
    xmin, xmax = max(roi_min[0], near - 2.0), min(roi_max[0], 45.0, far + 10.0)
    ymin, ymax = max(roi_min[1], -20.0, -wide - 4.0), min(roi_max[1], 20.0, wide + 4.0)
    xmax = max(xmax, min(roi_max[0], 20.0))
    ymin, ymax = min(ymin, max(roi_min[1], -8.0)), max(ymax, min(roi_max[1], 8.0))
    def P(pts):  # vehicle (x, y) -> picture (y, x); the horizontal axis is inverted below
        return [(y, x) for x, y in pts]
    width = 7.0
    height = min(11.0, max(4.0, width * (xmax - xmin) / (ymax - ymin) * 0.92 + 0.8))
    fig, a = plt.subplots(figsize=(width, height))
    a.set_facecolor("#fbfbfb")
    lamp_x, lamp_y = ctx["lamp_position"][:2]
    if ctx["segments"]:
        cmd = ctx["lamp_at"](t_ns)
        for i, s in enumerate(ctx["segments"]):
            lv = cmd.levels[i] if cmd is not None and i < len(cmd.levels) else 0.0
            if lv > 0:  # azimuth from +x toward +y; in the picture the angle is 90 deg - azimuth
                a.add_patch(Wedge((lamp_y, lamp_x), 0.9 * xmax, 90 - s["azimuth_max_deg"], 90 - s["azimuth_min_deg"],
                                  color="#ffd000", alpha=0.12 + 0.3 * lv, lw=0, zorder=0))
    pts = points_in(arr, ctx["points"].get(t_ns), ctx["root_T"])
    if pts is not None:
        a.scatter(pts[:, 1], pts[:, 0], s=1.2, c="#606060", alpha=0.6, lw=0, zorder=1)
    w = d["half_width"] + d["margin"]
    length = d["front"] + d["stopping"]
    corridor = P([(0, -w), (length, -w), (length, w), (0, w)])
    a.add_patch(Polygon(corridor, closed=True, fc="#30a0ff", alpha=0.25, lw=0, zorder=2))
    a.add_patch(Polygon(corridor, closed=True, fill=False, ec="#1070d0", lw=1.0, zorder=2))
    if d["model"] == "paper":  # the paper's front section |y| < w ahead
        for s in (-1, 1):
            a.plot([s * d["half_width"]] * 2, [0, xmax], ls="--", lw=0.8, color="#1070d0", zorder=2)
    else:  # the corridor swept along the vehicle's twist over the reaction time
        v = math.hypot(arr.ego_twist.linear.x, arr.ego_twist.linear.y)
        wz = arr.ego_twist.angular.z
        if v > 0.1 and arr.ego_twist.linear.x > 0:
            left, right = [], []
            x = y = h = 0.0
            n = 40
            dt = d["reaction_time"] / n
            for _ in range(n + 1):
                for side, lst in ((1, left), (-1, right)):
                    lst.append((x + length * math.cos(h) - side * w * math.sin(h),
                                y + length * math.sin(h) + side * w * math.cos(h)))
                turn = wz * dt
                x += v * dt * math.cos(h)
                y += v * dt * math.sin(h)
                h += turn
            a.add_patch(Polygon(P(left + right[::-1]), closed=True, fc="#30a0ff", alpha=0.1, lw=0, zorder=2))
            a.add_patch(Polygon(P(left + right[::-1]), closed=True, fill=False, ec="#1070d0", lw=0.7, ls=":",
                                zorder=2))
    ex0, ey0, ex1, ey1 = ctx["ego_box"]
    a.add_patch(Polygon(P([(ex0, ey0), (ex1, ey0), (ex1, ey1), (ex0, ey1)]), closed=True, fc="#303030", zorder=5))
    truth = ctx["truth"].get(t_ns)
    if truth is not None:
        for g in truth.objects:
            yaw = 2 * math.atan2(g.pose.orientation.z, g.pose.orientation.w)
            c, s = math.cos(yaw), math.sin(yaw)
            hl, hw = 0.5 * g.dimensions.x, 0.5 * g.dimensions.y
            poly = [(g.pose.position.x + c * dx - s * dy, g.pose.position.y + s * dx + c * dy)
                    for dx, dy in ((hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw))]
            a.add_patch(Polygon(P(poly), closed=True, fill=bool(g.dangerous), fc="#30a050", alpha=0.3, lw=0, zorder=3))
            a.add_patch(Polygon(P(poly), closed=True, fill=False, ec="#30a050", lw=1.3, zorder=3))
    for o in arr.obstacles:
        ms = motion_state(o)
        ls = {"static": "--", "moving": "-"}.get(ms, ":" if ms is not None else "-")
        colour = "#e02020" if o.dangerous else "#2060d0"
        if o.dangerous:
            a.add_patch(Polygon(P(box_corners(o)), closed=True, fc=colour, alpha=0.35, lw=0, zorder=4))
        a.add_patch(Polygon(P(box_corners(o)), closed=True, fill=False, ec=colour, lw=1.6 if o.dangerous else 0.9,
                            ls=ls, zorder=4))
        vx, vy = o.velocity_over_ground.x, o.velocity_over_ground.y
        if math.hypot(vx, vy) > 0.2:
            a.add_patch(FancyArrowPatch((o.pose.position.y, o.pose.position.x),
                                        (o.pose.position.y + vy, o.pose.position.x + vx),
                                        arrowstyle="->", mutation_scale=9, color=colour, lw=1.1, zorder=6))
        if o.dangerous or o.id in highlight:
            # At the box's near-left corner, kept inside the picture (a box cut by its edge).
            lx = min(max(o.aabb_max.x, xmin + 1.0), xmax - 1.5)
            ly = min(max(o.aabb_min.y, ymin + 1.5), ymax - 0.5)
            a.annotate(str(o.id), (ly, lx), fontsize=8, color=colour, weight="bold", zorder=7,
                       xytext=(2, 2), textcoords="offset points")
    a.set_xlim(ymax, ymin)  # +y (left) on the left
    a.set_ylim(xmin, xmax)
    a.set_aspect("equal")
    a.set_xlabel("y, left + [m]", fontsize=8)
    a.set_ylabel("x, forward [m] (%s)" % arr.header.frame_id, fontsize=8)
    a.tick_params(labelsize=8)
    a.grid(alpha=0.25)
    a.set_title(title, fontsize=9)
    legend = [Line2D([], [], color="#e02020", lw=2, label="flagged dangerous"),
              Line2D([], [], color="#2060d0", lw=1, label="tracked"),
              Line2D([], [], color="#1070d0", lw=6, alpha=0.3, label="corridor")]
    if any(motion_state(o) is not None for o in arr.obstacles):
        legend += [Line2D([], [], color="k", lw=1, ls="-", label="moving"),
                   Line2D([], [], color="k", lw=1, ls="--", label="static"),
                   Line2D([], [], color="k", lw=1, ls=":", label="motion unknown")]
    if truth is not None:
        legend.append(Line2D([], [], color="#30a050", lw=1.4, label="ground truth (filled: dangerous)"))
    if ctx["segments"]:
        legend.append(Line2D([], [], color="#ffd000", lw=6, alpha=0.5, label="lit segments"))
    a.legend(handles=legend, loc="upper center", bbox_to_anchor=(0.5, -0.07), ncol=4, fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


# ----------------------------------------------------------------------------- html

def fmt_s(ns, t0):
    return "%.2f" % (ns * 1e-9 - t0)


def render(args, out, profile_path, profile, binfo):
    import numpy as np
    meta = {}
    if os.path.isfile(os.path.join(out, "replay.json")):
        with open(os.path.join(out, "replay.json")) as f:
            meta = json.load(f)
    frames, lights, lamp_cmds, points = read_record(out)
    if not frames:
        sys.exit("report: the graph answered no frame (%s)" % os.path.join(out, "replay.log"))
    ev = load_eval(os.path.join(out, "eval.json"))
    rows = read_rows(out)
    frame_ns = sorted(frames)
    period = int(np.median(np.diff(frame_ns))) if len(frame_ns) > 1 else 100000000
    t0 = frame_ns[0] * 1e-9
    t_end = frame_ns[-1] + period
    states = light_states(lights)
    eps = episodes_of(states, t_end)
    dd = get(profile, "danger_detector", default={}) or {}
    pr = dd.get("predictive", {}) or {}
    model = meta.get("danger_model") or (args.danger_model if args.danger_model not in ("", "profile")
                                         else dd.get("model", "paper"))
    danger = {"model": model, "half_width": dd.get("half_width_m", 0.7), "reaction_time": dd.get("reaction_time_s", 3.0),
              "margin": pr.get("margin_m", 0.3), "front": pr.get("vehicle_front_m", 0.5),
              "stopping": pr.get("stopping_margin_m", 1.0), "footprint_margin": pr.get("footprint_margin_m", 0.0),
              "static_prior_k": pr.get("static_prior_k", 0.0), "time_step": pr.get("time_step_s", 0.05),
              "velocity_std_k": pr.get("velocity_std_k", 1.0), "uncertainty_cap": pr.get("uncertainty_cap_m", 0.5),
              "off_frames": pr.get("off_frames", 2)}
    lc = get(profile, "light_controller", default={}) or {}
    segments = lc.get("segments") or []
    prep = get(profile, "obstacle_detector", "prep", default={}) or {}
    # A key the profile leaves out takes icanc's default (docs/parameters.md), as the nodelets do.
    roi = (prep.get("roi_min", [-20, -20, -3]), prep.get("roi_max", [60, 20, 3]))
    ego_min, ego_max = prep.get("ego_min", [-1, -1, -3]), prep.get("ego_max", [1, 1, 3])
    lamp_ns = [c.header.stamp.to_nsec() for c in lamp_cmds]

    def lamp_at(t):
        i = bisect.bisect_right(lamp_ns, t) - 1
        return lamp_cmds[i] if i >= 0 else None
    truth = binfo["truth"]
    has_truth = bool(truth)
    ctx = {"t0": t0, "frames": frames, "frame_ns": frame_ns, "episodes": eps, "truth": truth,
           "segments": segments, "lamp_cmds": lamp_cmds, "lamp_at": lamp_at, "danger": danger, "roi": roi,
           "ego_box": (ego_min[0], ego_min[1], ego_max[0], ego_max[1]),
           "lamp_position": lc.get("lamp_position_m", [0, 0, 0]), "points": points,
           "root_T": transforms(binfo["static_tf"]),
           "ego_source": meta.get("ego_motion_source") or get(profile, "ego_motion", "source", default="none")}
    if has_truth:
        ctx["truth_spans"] = truth_intervals(frame_ns, truth, period)
        ctx["perfect"] = perfect_lamp(frame_ns, truth, lc.get("tau_s", 3.0), lc.get("recheck_below_s", 1.0), t_end)
    draw_timeline(os.path.join(out, "timeline.png"), ctx)

    # Lamp on-time over the drive [first frame, last frame + one period]: each state holds until the next.
    on_ns = 0
    cur_on, cur_t = None, frame_ns[0]
    for s in states:
        t = min(max(s.header.stamp.to_nsec(), frame_ns[0]), t_end)
        if cur_on:
            on_ns += t - cur_t
        cur_on, cur_t = s.on, t
    if cur_on:
        on_ns += t_end - cur_t
    span_s = (t_end - frame_ns[0]) * 1e-9
    duty = on_ns * 1e-9 / span_s if span_s > 0 else 0.0
    seg_wh = None
    if segments and lamp_cmds:
        watts = [float(s.get("watts", 0.0)) for s in segments]
        e = 0.0
        for i, c in enumerate(lamp_cmds):
            a = max(c.header.stamp.to_nsec(), frame_ns[0])
            b = min(lamp_cmds[i + 1].header.stamp.to_nsec() if i + 1 < len(lamp_cmds) else t_end, t_end)
            if b > a:
                e += sum(w * lv for w, lv in zip(watts, c.levels)) * (b - a) * 1e-9
        seg_wh = (e / 3600.0, sum(watts) * span_s / 3600.0)
    import yaml
    with open(os.path.join(ROOT, "config", "lamps.yaml")) as f:
        catalogue = (yaml.safe_load(f) or {}).get("lamps", [])
    lat = [s.input_latency_ms for s in states if s.input_latency_ms > 0]

    H = []
    e = html.escape
    H.append("<!DOCTYPE html><html><head><meta charset='utf-8'><title>icanc drive report: %s</title>"
             % e(os.path.basename(meta.get("bag", args.bag))))
    H.append("<style>body{font-family:sans-serif;max-width:1150px;margin:1em auto;color:#222}"
             "table{border-collapse:collapse;font-size:13px;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;"
             "text-align:right}th{background:#eee}td.l,th.l{text-align:left}img{max-width:100%;border:1px solid #ddd}"
             ".ep{border-top:2px solid #888;margin-top:1.5em}.pics{display:flex;gap:8px;flex-wrap:wrap}"
             ".pics figure{margin:0;flex:1 1 45%}figcaption{font-size:12px;color:#555}</style></head><body>")
    H.append("<h1>Drive report: %s</h1>" % e(os.path.basename(meta.get("bag", args.bag))))
    H.append("<p>Profile <code>%s</code>, danger model <b>%s</b>, ego motion <b>%s</b>, cloud topic <code>%s</code>; "
             "%d frames answered of %d clouds, %.1f s. Replayed in lockstep on sim time through the graph "
             "(<code>launch/eval.launch</code>); %s.</p>"
             % (e(os.path.relpath(profile_path, ROOT) if profile_path.startswith(ROOT) else profile_path), e(model),
                e(ctx["ego_source"]), e(binfo["points_topic"]), len(frames), binfo["clouds"], span_s,
                "with ground truth" if has_truth else "no ground truth in the bag"))
    # Summary
    H.append("<h2>Summary</h2><table>")
    row = lambda k, v: H.append("<tr><th class='l'>%s</th><td class='l'>%s</td></tr>" % (k, v))  # noqa: E731
    row("lamp on", "%.1f s of %.1f s (duty %.1f %%), %d episode%s" % (on_ns * 1e-9, span_s, 100 * duty, len(eps),
                                                                     "" if len(eps) == 1 else "s"))
    if ev:
        row("lamp duty per frame (icanc_eval)", "%.1f %%" % (100 * ev["duty_cycle"]))
        row("cloud &rarr; lamp latency p50 / p99", "%.1f / %.1f ms (icanc_eval)" % (ev["latency_ms"]["p50"],
                                                                                 ev["latency_ms"]["p99"]))
    elif lat:
        row("cloud &rarr; lamp latency p50 / p99", "%.1f / %.1f ms" % (np.percentile(lat, 50), np.percentile(lat, 99)))
    dropped = binfo["clouds"] - (ev["processed"] if ev else len(frames))
    row("frames dropped", "%d of %d (no answer from the graph in time)" % (dropped, binfo["clouds"]))
    if ev and len(frames) < ev["processed"]:  # the recorder came up after the first answers
        row("frames missing here", "%d answered frames not recorded by the report" % (ev["processed"] - len(frames)))
    en = []
    for lamp in catalogue:
        wt = float(lamp.get("high_beam_w", 0))
        en.append("%s %.3g Wh against %.3g Wh always on (saves %.0f %%)" % (
            e(lamp.get("label", lamp["name"])), wt * on_ns * 1e-9 / 3600, wt * span_s / 3600, 100 * (1 - duty)))
    row("energy, binary lamp on high beam", "<br>".join(en))
    if seg_wh:
        row("energy, the profile's segmented lamp", "%.3g Wh against %.3g Wh with every segment on (saves %.0f %%)"
            % (seg_wh[0], seg_wh[1], 100 * (1 - seg_wh[0] / seg_wh[1]) if seg_wh[1] else 0))
    if has_truth:
        pt = sum((b - a) for a, b in ctx["perfect"]) * 1e-9
        row("perfect detector's lamp", "%.1f s (duty %.1f %%): the light controller on the truth's dangerous flags"
            % (pt, 100 * pt / span_s if span_s else 0))
    H.append("</table>")
    if ev and has_truth:
        d = ev["danger"]
        H.append("<h2>Scores against the ground truth (icanc_eval)</h2><table><tr><th>TP/FP/FN/TN</th><th>precision %</th>"
                 "<th>recall %</th><th>F1 %</th><th>episodes caught</th><th>min lead s</th><th>detection recall %</th>"
                 "<th>id switches</th><th>velocity RMSE m/s</th><th>lamp duty %</th><th>perfect detector's duty %</th></tr>")
        lead = "%.2f" % min(ev["lead_times_s"]) if ev["lead_times_s"] else "-"
        H.append("<tr><td>%d/%d/%d/%d</td><td>%.1f</td><td>%.1f</td><td>%.1f</td><td>%d/%d</td><td>%s</td><td>%.1f</td>"
                 "<td>%d</td><td>%.2f</td><td>%.1f</td><td>%.1f</td></tr></table>"
                 % (d["tp"], d["fp"], d["fn"], d["tn"], 100 * d["precision"], 100 * d["recall"], 100 * d["f1"],
                    ev["caught"], ev["episodes"], lead, 100 * ev["detection"]["recall"], ev["id_switches"],
                    ev["velocity_rmse"], 100 * ev["duty_cycle"], 100 * ev["truth_duty_cycle"]))
        lcs = ev.get("lamp_causes")
        if lcs:
            H.append("<p>What keeps the lamp on: the flagged object-frames by cause, and the lamp re-run on the true "
                     "danger's flags with that cause's alone, and on every cause but it (lamp duty %.1f %% with all).</p>"
                     "<table><tr><th class='l'>cause</th><th>object-frames</th><th>duty alone %%</th>"
                     "<th>duty without %%</th></tr>" % (100 * lcs["duty_all"]))
            for n in CAUSE_NAMES:
                c = lcs.get(n, {})
                H.append("<tr><td class='l'>%s: %s</td><td>%d</td><td>%.1f</td><td>%.1f</td></tr>" % (
                    n, e(CAUSE_TEXT[n]), c.get("object_frames", 0), 100 * c.get("duty_alone", 0),
                    100 * c.get("duty_without", 0)))
            H.append("</table>")
    H.append("<h2>Timeline</h2><img src='timeline.png' alt='timeline'>")
    # Episodes
    H.append("<h2>Lamp-on episodes</h2><table id='episodes'><tr><th>#</th><th>on at s</th><th>off at s</th>"
             "<th>duration s</th><th class='l'>reason</th><th>flagged objects</th><th class='l'>flagged longest</th>"
             "<th class='l'>kept the lamp on: ids flagged in the frames that (re)started its timer</th></tr>")
    details = []
    for k, (s, eend, on, off) in enumerate(eps, 1):
        first = on.cloud_stamp.to_nsec() if on.reason == 1 and on.cloud_stamp.to_nsec() in frames else None
        if first is None:
            i = bisect.bisect_left(frame_ns, s)
            first = frame_ns[min(i, len(frame_ns) - 1)]
        in_ep = [t for t in frame_ns if first <= t < eend]
        objs = {}
        for t in in_ep:
            for o in frames[t].obstacles:
                if o.dangerous:
                    objs.setdefault(o.id, []).append((t, o))
        longest = max(objs, key=lambda i: (len(objs[i]), -i)) if objs else None
        # The frames whose flags (re)started the timer (LightState.cloud_stamp): the objects flagged
        # in them are what kept the lamp on; the other flags fell while the timer had time left.
        triggers = sorted({st.cloud_stamp.to_nsec() for st in states
                           if st.reason == 1 and s <= st.header.stamp.to_nsec() < eend} & set(frames))
        restarts = {}
        for t in triggers:
            for o in frames[t].obstacles:
                if o.dangerous:
                    restarts[o.id] = restarts.get(o.id, 0) + 1
        kept = sorted(restarts, key=lambda i: (-restarts[i], i))
        H.append("<tr data-episode='%d' data-start='%.3f' data-end='%.3f'><td><a href='#episode-%d'>%d</a></td><td>%s</td>"
                 "<td>%s</td><td>%.2f</td><td class='l'>%s</td><td>%d</td><td class='l'>%s</td><td class='l'>%s</td></tr>"
                 % (k, s * 1e-9, eend * 1e-9, k, k, fmt_s(s, t0), fmt_s(eend, t0) if off else "end", (eend - s) * 1e-9,
                    e(on.reason_text or REASONS.get(on.reason, "?")), len(objs),
                    "id %d, %d frames" % (longest, len(objs[longest])) if longest is not None else "-",
                    ", ".join("id %d (%d of %d)" % (i, restarts[i], len(triggers)) for i in kept[:6])
                    + (", &hellip;" if len(kept) > 6 else "") if kept else "-"))
        details.append((k, s, eend, on, first, in_ep, objs, longest, restarts, triggers))
    H.append("</table>")
    for k, s, eend, on, first, in_ep, objs, longest, restarts, triggers in details:
        H.append("<div class='ep' id='episode-%d' data-start='%.3f' data-end='%.3f'>" % (k, s * 1e-9, eend * 1e-9))
        H.append("<h3>Episode %d: %s s &ndash; %s s, %s</h3>" % (k, fmt_s(s, t0), fmt_s(eend, t0),
                                                                  e(on.reason_text or REASONS.get(on.reason, "?"))))
        pics = [(first, "first frame", "ep%03d_first.png" % k)]
        if longest is not None:
            t_long = objs[longest][-1][0]
            if t_long != first:
                pics.append((t_long, "id %d's last flagged frame (flagged longest: %d frames)" % (longest, len(objs[longest])),
                             "ep%03d_longest.png" % k))
        H.append("<div class='pics'>")
        for t, what, name in pics:
            nflag = sum(o.dangerous for o in frames[t].obstacles)
            draw_bev(os.path.join(out, name), ctx, t,
                     "episode %d, %s: t = %s s, %d flagged" % (k, what, fmt_s(t, t0), nflag),
                     {longest} if longest is not None else set())
            H.append("<figure><img src='%s' alt='episode %d %s'><figcaption>%s, t = %s s</figcaption></figure>"
                     % (name, k, e(what), e(what), fmt_s(t, t0)))
        H.append("</div>")
        if not objs:
            H.append("<p>No object flagged in this episode (%s).</p>" % e(on.reason_text or REASONS.get(on.reason, "?")))
            H.append("</div>")
            continue
        H.append("<p>The timer was (re)started by %d frame%s; an object flagged in none of them did not keep the lamp on.</p>"
                 "<table class='flagged' data-episode='%d'><tr><th>id</th><th>timer (re)starts</th><th>flagged frames</th>"
                 "<th>first flagged s</th>"
                 "<th>x m</th><th>y m</th><th>size l&times;w m</th><th>speed over ground m/s</th><th>relative m/s</th>"
                 "<th>track age</th>%s<th class='l'>why flagged (first flag)</th>%s</tr>"
                 % (len(triggers), "" if len(triggers) == 1 else "s", k, "<th>motion</th>" if any(motion_state(o) is not None for v in objs.values() for _, o in v) else "",
                    "<th class='l'>against the ground truth</th>" if has_truth else ""))
        for oid in sorted(objs, key=lambda i: (-restarts.get(i, 0), -len(objs[i]), i)):
            t, o = objs[oid][0]
            ms = motion_state(o)
            truth_col = ""
            if has_truth:
                cs = {}
                for tt, _ in objs[oid]:
                    c = rows.get((int(round(tt * 1e-6)), oid), ("unscored", "not in the scored rows"))
                    cs.setdefault(c[0], [0, c[1]])[0] += 1
                truth_col = "<td class='l'>%s</td>" % "<br>".join(
                    "%s &times;%d: %s" % (n, v[0], e(v[1])) for n, v in sorted(cs.items(), key=lambda x: -x[1][0]))
            H.append("<tr data-id='%d'><td>%d</td><td>%d</td><td>%d</td><td>%s</td><td>%.1f</td><td>%.1f</td><td>%.1f&times;%.1f</td>"
                     "<td>%.1f</td><td>%.1f</td><td>%d</td>%s<td class='l'>%s</td>%s</tr>"
                     % (oid, oid, restarts.get(oid, 0), len(objs[oid]), fmt_s(t, t0), o.pose.position.x, o.pose.position.y,
                        o.dimensions.x, o.dimensions.y, math.hypot(o.velocity_over_ground.x, o.velocity_over_ground.y),
                        o.speed, o.age, "<td>%s</td>" % e(ms) if ms is not None else "", e(why_flagged(o, frames[t], danger)),
                        truth_col))
        H.append("</table></div>")
    H.append("<h2>How to read this</h2><p>Bird's-eye pictures: grey dots are the detector's non-ground points, red "
             "boxes the obstacles flagged dangerous, blue ones the other tracked obstacles (dashed: standing still, "
             "when the tracker reports a motion state), arrows their velocity over ground (where they are in 1 s), "
             "the blue band the danger model's corridor (|y| &le; half-width + margin, 0 &le; x &le; vehicle front + "
             "stopping margin)%s; green boxes the ground truth (filled: truly dangerous). An episode runs from the "
             "light state that switched the lamp on to the one that switched it off; its flagged objects are those "
             "flagged in the frames from the cloud that started it up to the switch off. The lamp's on-time and "
             "energy count each light state until the next over the frames' span.</p>"
             % (", the dashed lines the paper's front section |y| &lt; half-width" if model == "paper"
                else ", the dotted band the corridor swept along the vehicle's twist over the reaction time"))
    H.append("</body></html>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(H))
    print("report: wrote %s (%d episodes)" % (os.path.join(out, "index.html"), len(eps)), file=sys.stderr)


def main(argv):
    args = parse_args(argv)
    bag = os.path.abspath(args.bag)
    if not os.path.isfile(bag):
        sys.exit("report: no bag " + bag)
    out = os.path.abspath(args.out_dir)
    os.makedirs(out, exist_ok=True)
    profile_path, profile = load_profile(args)
    binfo = inspect_bag(bag, args.points_topic)
    if not binfo["clouds"]:
        sys.exit("report: %s: no clouds on %s" % (bag, binfo["points_topic"]))
    if not args.render_only:
        for name in ("record.bag", "eval.json", "rows.csv"):
            if os.path.exists(os.path.join(out, name)):
                os.remove(os.path.join(out, name))
        replay(args, bag, out, profile_path, profile, binfo)
    render(args, out, profile_path, profile, binfo)


if __name__ == "__main__":
    main(sys.argv[1:])
