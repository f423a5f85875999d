"""ROS 2 bags written by rosbags (a pure-Python ROS 2 bag library with the standard message
definitions built in, no ROS install), read by `safereach monitor`: an independent writer
for the Rust reader, whose own tests write their bags with a hand-written CDR encoder. The
seed's 0.2 / 0.25 example as a rosbag2 MCAP bag gives the events of its CSV."""

import csv
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

# CI installs rosbags and builds the binary, and must not skip what it cannot run.
REQUIRED = os.environ.get("SAFEREACH_CI") == "1"
if not REQUIRED:
    pytest.importorskip("rosbags")
from rosbags.rosbag2 import StoragePlugin, Writer  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = ROOT / "target" / "release" / "safereach"
TRACE = ROOT / "tests" / "fixtures" / "seed-w0.25.run.csv"

# Autoware's tracked objects, from autoware_msgs' .msg files (field order is what CDR encodes).
AUTOWARE = {
    "unique_identifier_msgs/msg/UUID": "uint8[16] uuid\n",
    "autoware_perception_msgs/msg/ObjectClassification": "uint8 label\nfloat32 probability\n",
    "autoware_perception_msgs/msg/Shape": (
        "uint8 type\ngeometry_msgs/Polygon footprint\ngeometry_msgs/Vector3 dimensions\n"
    ),
    "autoware_perception_msgs/msg/TrackedObjectKinematics": (
        "geometry_msgs/PoseWithCovariance pose_with_covariance\n"
        "geometry_msgs/TwistWithCovariance twist_with_covariance\n"
        "geometry_msgs/AccelWithCovariance acceleration_with_covariance\n"
        "uint8 orientation_availability\nbool is_stationary\n"
    ),
    "autoware_perception_msgs/msg/TrackedObject": (
        "unique_identifier_msgs/UUID object_id\nfloat32 existence_probability\n"
        "autoware_perception_msgs/ObjectClassification[] classification\n"
        "autoware_perception_msgs/TrackedObjectKinematics kinematics\n"
        "autoware_perception_msgs/Shape shape\n"
    ),
    "autoware_perception_msgs/msg/TrackedObjects": (
        "std_msgs/Header header\nautoware_perception_msgs/TrackedObject[] objects\n"
    ),
}


@pytest.fixture(scope="module")
def store():
    ts = get_typestore(Stores.ROS2_HUMBLE)
    types = {}
    for name, text in AUTOWARE.items():
        if name not in ts.types:
            types.update(get_types_from_msg(text, name))
    ts.register(types)
    return ts


@pytest.fixture(scope="module")
def certificate(tmp_path_factory):
    if not BINARY.exists() and not REQUIRED:
        pytest.skip("the safereach binary is not built")
    path = tmp_path_factory.mktemp("cert") / "cert.json"
    subprocess.run([str(BINARY), "certify", str(ROOT / "problems" / "seed.toml"), "--set",
                    "environment.obstacle_speed=0.2", "--out", str(path)], check=True,
                   stdout=subprocess.DEVNULL)
    return path


def stamp(ts, text):
    sec, _, frac = text.partition(".")
    return ts.types["builtin_interfaces/msg/Time"](sec=int(sec), nanosec=int(frac.ljust(9, "0")))


def body(ts, x, quaternion, speed):
    """Pose and body-frame twist with covariance, at x on the lane (the frame's x axis)."""
    T = ts.types
    pose = T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=x, y=0.0, z=0.0),
        orientation=T["geometry_msgs/msg/Quaternion"](*quaternion))
    zero = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
    twist = T["geometry_msgs/msg/Twist"](
        linear=T["geometry_msgs/msg/Vector3"](x=speed, y=0.0, z=0.0), angular=zero)
    cov = np.arange(36, dtype=np.float64)
    return (T["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=cov),
            T["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=cov))


AHEAD = (0.0, 0.0, 0.0, 1.0)   # yaw 0: along the lane
FACING = (0.0, 0.0, 1.0, 0.0)  # yaw pi: towards the robot


def write_bag(ts, directory, tracked):
    T = ts.types
    odom, text = "nav_msgs/msg/Odometry", "std_msgs/msg/String"
    objects = "autoware_perception_msgs/msg/TrackedObjects"
    with open(TRACE) as f:
        rows = list(csv.DictReader(f))
    with Writer(directory, version=8, storage_plugin=StoragePlugin.MCAP) as w:
        robot = w.add_connection("/odom", odom, typestore=ts)
        mode = w.add_connection("/mode", text, typestore=ts)
        obstacle = (w.add_connection("/perception/objects", objects, typestore=ts) if tracked
                    else w.add_connection("/obstacles/0", odom, typestore=ts))
        for k, r in enumerate(rows):
            st = stamp(ts, r["t"])
            header = T["std_msgs/msg/Header"](stamp=st, frame_id="odom")
            log = 10**6 * k
            pose, twist = body(ts, float(r["robot_x"]), AHEAD, float(r["robot_v"]))
            msg = T[odom](header=header, child_frame_id="base_link", pose=pose, twist=twist)
            w.write(robot, log, ts.serialize_cdr(msg, odom))
            w.write(mode, log, ts.serialize_cdr(T[text](data=r["robot_mode"]), text))
            pose, twist = body(ts, float(r["obstacle_x"]), FACING, float(r["obstacle_v"]))
            if tracked:
                zero = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
                accel = T["geometry_msgs/msg/AccelWithCovariance"](
                    accel=T["geometry_msgs/msg/Accel"](linear=zero, angular=zero),
                    covariance=np.zeros(36))
                kin = T["autoware_perception_msgs/msg/TrackedObjectKinematics"](
                    pose_with_covariance=pose, twist_with_covariance=twist,
                    acceleration_with_covariance=accel, orientation_availability=2,
                    is_stationary=False)
                shape = T["autoware_perception_msgs/msg/Shape"](
                    type=0, footprint=T["geometry_msgs/msg/Polygon"](points=[
                        T["geometry_msgs/msg/Point32"](x=0.0, y=0.0, z=0.0)]),
                    dimensions=T["geometry_msgs/msg/Vector3"](x=0.5, y=0.5, z=1.7))
                obj = T["autoware_perception_msgs/msg/TrackedObject"](
                    object_id=T["unique_identifier_msgs/msg/UUID"](
                        uuid=np.arange(16, dtype=np.uint8)),
                    existence_probability=0.9,
                    classification=[T["autoware_perception_msgs/msg/ObjectClassification"](
                        label=7, probability=0.8)],
                    kinematics=kin, shape=shape)
                msg = T[objects](header=header, objects=[obj])
                w.write(obstacle, log, ts.serialize_cdr(msg, objects))
            else:
                msg = T[odom](header=header, child_frame_id="0", pose=pose, twist=twist)
                w.write(obstacle, log, ts.serialize_cdr(msg, odom))
    (bag,) = pathlib.Path(directory).glob("*.mcap")
    return bag


def monitor(certificate, trace, *flags):
    out = subprocess.run([str(BINARY), "monitor", "--certificate", str(certificate), "--json",
                          str(trace), *flags], capture_output=True, text=True)
    lines = [json.loads(line) for line in out.stdout.splitlines()]
    return out.returncode, lines[:-1], lines[-1]["summary"]


def without(event, *keys):
    return {k: v for k, v in event.items() if k not in keys}


@pytest.mark.parametrize("tracked", [False, True])
def test_a_rosbags_bag_gives_the_events_of_its_csv(store, certificate, tmp_path, tracked):
    bag = write_bag(store, tmp_path / "run", tracked)
    code, events, summary = monitor(certificate, TRACE)
    flags = ["--obstacle-topic", "/obstacles/*", "--obstacle-topic", "/perception/*",
             "--mode-topic", "/mode", "--ground-truth"]
    bag_code, bag_events, bag_summary = monitor(certificate, bag, *flags)
    assert code == bag_code == 1
    drop = ("line", "obstacle_id") if tracked else ("line",)
    assert [without(e, *drop) for e in bag_events] == [without(e, *drop) for e in events]
    for key in ("verdict", "samples", "instants", "violations", "premises", "behaviour"):
        assert bag_summary[key] == summary[key], key
    if tracked:
        assert bag_summary["first_violation"]["obstacle_id"] == bytes(range(16)).hex()


def test_monitor_observe_bag_is_the_command_line(store, certificate, tmp_path):
    import safereach as sr

    bag = write_bag(store, tmp_path / "run", tracked=True)
    m = sr.Monitor(sr.Certificate.from_json(certificate.read_text()))
    verdict, events = m.observe_bag(bag, obstacle_topics=["/perception/*"], mode_topic="/mode",
                                    ground_truth=True)
    code, cli_events, summary = monitor(certificate, bag, "--obstacle-topic", "/perception/*",
                                        "--mode-topic", "/mode", "--ground-truth")
    assert verdict == "violated" and code == 1
    assert [message for message, _ in events] == [e["line"] for e in cli_events]
    for (_, e), c in zip(events, cli_events):
        assert e["obstacle_id"] == c["obstacle_id"] == bytes(range(16)).hex()
        assert (e["premise"], e["t"], e["observed"]) == (c["premise"], c["t"], c["observed"])
    assert m.summary()["violations"] == summary["violations"]
    with pytest.raises(sr.InputError, match="obstacle_speed"):
        m.observe_bag(bag, obstacle_speed="radar")
    with pytest.raises(sr.InputError, match="cannot open the bag"):
        m.observe_bag(tmp_path / "missing.mcap")
