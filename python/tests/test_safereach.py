"""The Python package against independent answers: the closed form of the safe radius, the
exact check, the monitor's README example, and the command line's messages for bad input."""

import json
import math
import pathlib
import subprocess

import numpy as np
import pytest

import safereach as sr

ROOT = pathlib.Path(__file__).resolve().parents[2]
SEED = ROOT / "problems" / "seed.toml"


def seed(**sets):
    p = sr.Problem.from_file(str(SEED))
    for key, value in sets.items():
        p.set(key.replace("__", "."), value)
    return p


def test_certify_and_check_round_trip_through_json():
    cert = sr.certify(seed())
    assert cert.verdict == "certified"
    assert cert.lower_bound <= cert.min_separation
    assert abs(cert.min_separation - 0.33) < 1e-6
    assert sr.check(cert) == "certified"
    again = sr.Certificate.from_json(cert.to_json())
    assert sr.check(again) == "certified"
    assert again.to_json() == cert.to_json()
    names = [p["name"] for p in cert.premises]
    assert "obstacle_speed" in names and "latency" in names


def test_the_json_is_what_the_command_line_writes(tmp_path):
    out = tmp_path / "cli.json"
    binary = ROOT / "target" / "release" / "safereach"
    if not binary.exists():
        pytest.skip("the safereach binary is not built")
    subprocess.run([str(binary), "certify", str(SEED), "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL)
    assert sr.certify(seed()).to_json() == out.read_text()


def test_a_tampered_certificate_is_rejected_with_the_reason():
    data = json.loads(sr.certify(seed()).to_json())
    data["lower_bound"] = data["lower_bound"] + 1.0
    forged = sr.Certificate.from_json(json.dumps(data))
    with pytest.raises(sr.CertificateError) as e:
        sr.check(forged)
    assert "digest" in str(e.value) or "bound" in str(e.value)
    with pytest.raises(sr.CertificateError):
        sr.Monitor(forged)


def test_a_refutation_carries_a_colliding_witness():
    cert = sr.certify(seed(environment__obstacle_speed=0.3))
    assert cert.verdict == "refuted"
    assert cert.witness["collides"] is True
    assert sr.check(cert) == "refuted"


def test_safe_radius_matches_the_brake_on_entry_closed_form():
    # Rule `area`, latency 0, a robot cruising from the start: rho* = v^2/(2b) + W v/b
    # + (v + W) dt + clearance (KeYmaera X's form, as the Rust tests use it).
    v, b, dt = 0.2, 0.05, 0.1
    for w in (0.05, 0.1, 0.15):
        p = seed(controller__danger_rule="area", robot__latency=0, robot__initial_speed=v)
        p.set("controller.wrong_assumption_brake", False)
        closed = v * v / (2 * b) + w * v / b + (v + w) * dt
        got = sr.safe_radius(p, [w])[0]
        assert got == pytest.approx(closed, abs=2e-6), (w, got, closed)
    single = sr.safe_radius(seed())
    assert isinstance(single, float)


def test_max_speed_is_where_certify_changes_its_answer():
    w = sr.max_speed(seed())
    assert w is not None and 0.0 < w < 1.0
    assert sr.certify(seed(environment__obstacle_speed=w - 1e-4)).verdict == "certified"
    assert sr.certify(seed(environment__obstacle_speed=w + 1e-4)).verdict != "certified"


def test_problems_from_text_and_dict_and_scenes():
    text = SEED.read_text()
    assert sr.Problem(text).name == "seed"
    import tomllib
    d = tomllib.loads(text)
    assert sr.certify(sr.problem_from_dict(d)).verdict == "certified"
    scene = sr.Problem.from_file(str(ROOT / "problems" / "seed-lanes.toml"))
    assert scene.is_scene
    cert = sr.certify(scene)
    assert cert.verdict == "certified" and sr.check(cert) == "certified"


def test_bad_input_raises_with_the_command_lines_message():
    with pytest.raises(sr.InputError) as e:
        seed(robot__braking=-1.0)
    assert "robot.braking" in str(e.value) and "> 0" in str(e.value)
    p = seed()
    with pytest.raises(sr.InputError) as e:
        p.set("robot.no_such_key", 1.0)
    assert "no_such_key" in str(e.value)
    with pytest.raises(sr.InputError) as e:
        p.set("environment.obstacle_speed", math.inf)
    assert "obstacle_speed" in str(e.value)
    assert sr.certify(p).verdict == "certified", "a refused set leaves the problem as it was"
    with pytest.raises(sr.InputError) as e:
        sr.Problem.from_file(str(ROOT / "no-such-file.toml"))
    assert "no-such-file.toml" in str(e.value)
    with pytest.raises(sr.InputError):
        sr.Certificate.from_json("[1, 2]")


def read_trace(path):
    header, *rows = path.read_text().splitlines()
    cols = header.split(",")
    return [dict(zip(cols, r.split(","))) for r in rows]


def test_the_monitor_flags_the_seeds_run_at_025_as_the_command_line_does(tmp_path):
    """The README's worked example: certified for W = 0.2, run at up to 0.25."""
    cert = sr.certify(seed(environment__obstacle_speed=0.2))
    trace = ROOT / "tests" / "fixtures" / "seed-w0.25.run.csv"
    rows = read_trace(trace)
    m = sr.Monitor(cert)
    first = None
    for r in rows:
        verdict, events = m.observe(float(r["t"]), float(r["robot_x"]), float(r["robot_v"]),
                                    float(r["obstacle_x"]), obstacle_v=float(r["obstacle_v"]),
                                    robot_mode=r["robot_mode"])
        if events and first is None:
            first = events[0]
    assert m.verdict == "violated"
    assert first["premise"] == "obstacle_speed" and first["action"] == "brake"
    assert first["observed"] > first["bound"] == pytest.approx(0.2)
    summary = m.summary()
    assert summary["verdict"] == "violated" and summary["samples"] == len(rows)

    binary = ROOT / "target" / "release" / "safereach"
    if not binary.exists():
        pytest.skip("the safereach binary is not built")
    path = tmp_path / "cert.json"
    path.write_text(cert.to_json())
    out = subprocess.run([str(binary), "monitor", "--certificate", str(path), str(trace),
                          "--json"], capture_output=True, text=True)
    assert out.returncode == 1
    cli = json.loads(out.stdout.splitlines()[-1])["summary"]
    assert cli["violations"] == summary["violations"]
    assert cli["first_violation"]["t"] == first["t"]
    assert cli["first_violation"]["observed"] == first["observed"]


def test_observe_many_equals_observe_one_by_one():
    cert = sr.certify(seed(environment__obstacle_speed=0.2))
    rows = read_trace(ROOT / "tests" / "fixtures" / "seed-w0.25.run.csv")
    col = lambda k: np.array([float(r[k]) for r in rows])
    one = sr.Monitor(cert)
    singles = []
    for i, r in enumerate(rows):
        _, events = one.observe(float(r["t"]), float(r["robot_x"]),
                                float(r["robot_v"]), float(r["obstacle_x"]))
        singles += [(i, e) for e in events]
    many = sr.Monitor(cert)
    verdict, events = many.observe_many(col("t"), col("robot_x"), col("robot_v"),
                                        col("obstacle_x"))
    assert verdict == one.verdict == "violated"
    assert events == singles
    assert many.summary() == one.summary()
    with pytest.raises(sr.InputError):
        many.observe_many(col("t"), col("robot_x")[:3], col("robot_v"),
                          col("obstacle_x"))


def test_a_ros_style_node_brakes_when_the_monitor_says_so():
    from node_example import MonitorNode
    cert = sr.certify(seed(environment__obstacle_speed=0.2))
    node = MonitorNode(cert)
    for r in read_trace(ROOT / "tests" / "fixtures" / "seed-w0.25.run.csv"):
        node.on_message(float(r["t"]), float(r["robot_x"]), float(r["robot_v"]),
                        float(r["obstacle_x"]))
    assert node.commanded == "brake" and node.first_violation["premise"] == "obstacle_speed"


def test_region_maps_agree_with_certify_at_points_and_check_exactly():
    p = seed()
    ranges = {"environment.obstacle_speed": (0.10, 0.30), "controller.reaction_radius": (1.0, 1.6)}
    m = sr.region(p, ranges, depth=6)
    cov = m.coverage
    assert abs(cov["certified"] + cov["refuted"] + cov["undecided"] - 1.0) < 1e-9
    assert cov["certified"] > 0.3 and cov["refuted"] > 0.3
    m.check()
    again = sr.RegionMap.from_json(m.to_json())
    assert again.check() is False, "part of this box is refuted"
    for leaf in m.leaves:
        if leaf["verdict"] != "certified":
            continue
        (w0, w1) = leaf["box"]["environment.obstacle_speed"]
        (r0, r1) = leaf["box"]["controller.reaction_radius"]
        point = seed(environment__obstacle_speed=(w0 + w1) / 2,
                     controller__reaction_radius=(r0 + r1) / 2)
        assert sr.certify(point).verdict == "certified", leaf["box"]
    whole = sr.region(p, {"environment.obstacle_speed": (0.10, 0.20),
                          "controller.reaction_radius": (1.3, 1.6)})
    assert whole.check() is True
    with pytest.raises(sr.InputError) as e:
        sr.region(p, {"robot.braking": (0.04, 0.05)})
    assert "robot.braking" in str(e.value)


def test_scene_region_maps_range_an_obstacle_and_agree_at_leaf_centres():
    path = str(ROOT / "problems" / "scene-oncoming.toml")
    scene = sr.Problem.from_file(path)
    ranges = {"obstacle.1.max_speed": (0.10, 0.25), "controller.reaction_radius": (1.3, 1.6)}
    m = sr.region(scene, ranges, depth=5)
    assert m.check() is False, "part of this box is refuted"
    for leaf in m.leaves:
        if leaf["verdict"] != "certified":
            continue
        point = sr.Problem.from_file(path)
        (w0, w1) = leaf["box"]["obstacle.1.max_speed"]
        (r0, r1) = leaf["box"]["controller.reaction_radius"]
        point.set("obstacle.1.max_speed", (w0 + w1) / 2)
        point.set("controller.reaction_radius", (r0 + r1) / 2)
        assert sr.certify(point).verdict == "certified", leaf["box"]
    assert any(leaf["verdict"] == "certified" for leaf in m.leaves)
    with pytest.raises(sr.InputError) as e:
        sr.region(scene, {"obstacle.3.position": (4.0, 6.0)})
    assert "lane 1" in str(e.value)


def test_the_planar_monitor_holds_on_the_witness_trace_and_flags_a_robot_that_drives_on(tmp_path):
    """A planar certificate's witness trace, as the command line writes and reads it."""
    binary = ROOT / "target" / "release" / "safereach"
    if not binary.exists():
        pytest.skip("the safereach binary is not built")
    cert_path, trace = tmp_path / "seed.json", tmp_path / "seed.csv"
    problem = ROOT / "problems" / "planar" / "seed-in-plane.toml"
    subprocess.run([str(binary), "certify", str(problem), "--out", str(cert_path)], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run([str(binary), "simulate", "--replay", str(cert_path), "--trace", str(trace)],
                   check=True, stdout=subprocess.DEVNULL)
    cert = sr.Certificate.from_json(cert_path.read_text())
    assert sr.check(cert) == "certified"
    with pytest.raises(sr.CertificateError):
        sr.Monitor(cert)
    rows = read_trace(trace)

    def run(rows):
        m = sr.PlanarMonitor(cert)
        events = []
        for r in rows:
            v = (float(r["obstacle_vx"]), float(r["obstacle_vy"])) if r["obstacle_vx"] else (None, None)
            _, raised = m.observe(float(r["t"]), float(r["robot_x"]), float(r["robot_y"]),
                                  float(r["robot_v"]), obstacle=r["obstacle_id"],
                                  obstacle_x=float(r["obstacle_x"]),
                                  obstacle_y=float(r["obstacle_y"]),
                                  obstacle_vx=v[0], obstacle_vy=v[1],
                                  robot_mode=r["robot_mode"])
            events += raised
        return m, events

    m, events = run(rows)
    assert (m.verdict, events) == ("held", [])
    summary = m.summary()
    assert summary["plane"]["obstacles"][0]["seen"] and summary["samples"] == len(rows)
    brake = next(i for i, r in enumerate(rows) if r["robot_mode"] == "brake")
    rows[brake]["robot_mode"] = "drive"
    m, events = run(rows)
    assert m.verdict == "violated"
    assert [e["premise"] for e in events] == ["controller_reaction"]
    with pytest.raises(sr.CertificateError):
        sr.PlanarMonitor(sr.certify(seed()))


def test_planar_problems_certify_as_the_command_line_does_and_check_exactly(tmp_path):
    """The seed in the plane: the line's s* (0.33 m) inside a 1e-9 bracket, the certificate
    the command line writes byte for byte, a forged bound rejected; overrides and JSON keep
    it planar, and the refuting override is refuted with a colliding witness."""
    path = ROOT / "problems" / "planar" / "seed-in-plane.toml"
    p = sr.Problem.from_file(str(path))
    assert p.is_planar and not p.is_scene and p.name == "seed-in-plane"
    cert = sr.certify(p)
    assert cert.verdict == "certified" and sr.check(cert) == "certified"
    assert cert.lower_bound <= 0.33 <= cert.to_dict()["upper_bound"]
    assert cert.to_dict()["upper_bound"] - cert.lower_bound <= 1e-9 + 1e-12
    binary = ROOT / "target" / "release" / "safereach"
    if binary.exists():
        out = tmp_path / "cli.json"
        subprocess.run([str(binary), "certify", str(path), "--out", str(out)], check=True,
                       stdout=subprocess.DEVNULL)
        assert cert.to_json() == out.read_text()
    data = json.loads(cert.to_json())
    data["lower_bound"] = data["lower_bound"] + 1.0
    with pytest.raises(sr.CertificateError):
        sr.check(sr.Certificate.from_json(json.dumps(data)))
    p.set("obstacle.0.max_speed", 0.3)
    again = sr.Problem.from_json(p.to_json())
    assert again.is_planar and json.loads(again.to_json())["obstacle"][0]["max_speed"] == 0.3
    refuted = sr.certify(again)
    assert refuted.verdict == "refuted" and refuted.witness["collides"] is True
    assert sr.check(refuted) == "refuted"
    with pytest.raises(sr.InputError) as e:
        p.set("obstacle.0.max_speed", -1.0)
    assert "max_speed" in str(e.value)


def test_planar_radius_speed_and_region_answer_as_the_line_does():
    """The seed in the plane: its smallest safe radius and largest safe speed are the
    line's to the planar search's resolution (1e-3), and its region map over a certified
    box checks as certified whole."""
    planar = sr.Problem.from_file(str(ROOT / "problems" / "planar" / "seed-in-plane.toml"))
    line = sr.Problem.from_file(str(ROOT / "problems" / "seed.toml"))
    radius = sr.safe_radius(planar)
    assert abs(radius - sr.safe_radius(line)) <= 1.5e-3
    assert sr.safe_radius(planar, [0.15]) == [radius]  # the file's speed bound, as a list
    assert abs(sr.max_speed(planar) - sr.max_speed(line)) <= 1.5e-3
    m = sr.region(planar, {"controller.reaction_radius": (1.3, 1.6),
                           "obstacle.0.max_speed": (0.1, 0.2)}, depth=2)
    assert m.check() is True and m.coverage["certified"] == 1.0
    with pytest.raises(sr.InputError) as e:
        sr.region(planar, {"sensing.gap_noise": (0.0, 0.1)})
    assert "Lemma P7" in str(e.value)
