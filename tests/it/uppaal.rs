//! The UPPAAL export (`safereach::crosscheck::uppaal`, `safereach export-uppaal`).
//!
//! UPPAAL is not available here, so the export is checked three ways:
//! - structure: the XML is well formed and has the shape UPPAAL reads (an `nta` root with a
//!   `declaration`, `template`s with `name`, `location`s, `init` and `transition`s whose
//!   references resolve, a `system`), the seed's location names, the guard functions, the
//!   query file;
//! - numbers: the constants in the file, divided by the stated scale, are the problem's exact
//!   numbers (the grid is exact, nothing is rounded);
//! - behaviour: the network the XML is printed from, run by the interpreter
//!   ([`safereach::crosscheck::uppaal::explore_grid`]), answers what the explorer answers on the same
//!   finite model — verdict, shortest collision period and minimum separation — over every
//!   danger rule, latencies 0–3 and W below and above V_a, and (latencies 0–2) with weaker
//!   brakes, a moving start, a range of initial gaps, sensing noise and occlusion. Broken
//!   variants of the network are caught by the interpreter (it has teeth).

use std::collections::{BTreeSet, HashMap};

use roxmltree::{Document, Node};
use safereach::core::model::{Controller, DangerRule, Position, Problem, Sensing};
use safereach::core::num::Exact;
use safereach::crosscheck::explore::{self, ExploreVerdict, Options, SpeedSet};
use safereach::crosscheck::uppaal::{self, Decl, UppaalError, UppaalModel};

use crate::common::cli::{bad_input_exits_2, files, safereach, stdout};
use crate::common::paths::{load_problem, problem_file, seed_file};
use crate::common::spec::Spec;
use crate::common::tmp;

fn seed() -> Problem {
    load_problem("seed.toml", &[])
}

fn export(p: &Problem, speeds: &str) -> UppaalModel {
    let set = SpeedSet::parse(speeds, &p.params::<Exact>().W).unwrap();
    uppaal::export(p, &set).expect("the problem exports")
}

/// [`Spec::small`] with the numbers the tests vary.
fn small(rule: DangerRule, latency: u32, w: f64, wab: bool, rho: f64, g0: f64) -> Problem {
    Spec {
        name: "uppaal-test",
        rule,
        latency,
        w,
        wab,
        rho,
        g0,
        ..Spec::small()
    }
    .problem()
}

// ---------------------------------------------------------------------------------------------
// Structure
// ---------------------------------------------------------------------------------------------

fn elements<'a, 'i>(node: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(|n| n.is_element())
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Node<'a, 'i> {
    elements(node)
        .find(|n| n.has_tag_name(tag))
        .unwrap_or_else(|| panic!("<{}> has no <{tag}>", node.tag_name().name()))
}

/// Checks the shape UPPAAL reads; returns each template's location names.
fn check_structure(xml: &str) -> HashMap<String, Vec<String>> {
    let doc = Document::parse_with_options(
        xml,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("the XML is well formed");
    let nta = doc.root_element();
    assert_eq!(nta.tag_name().name(), "nta");
    let tags: Vec<&str> = elements(nta).map(|n| n.tag_name().name()).collect();
    assert_eq!(
        tags,
        ["declaration", "template", "template", "system", "queries"],
        "UPPAAL's element order"
    );
    let mut ids = BTreeSet::new();
    let mut out = HashMap::new();
    for t in elements(nta).filter(|n| n.has_tag_name("template")) {
        let kids: Vec<&str> = elements(t).map(|n| n.tag_name().name()).collect();
        assert_eq!(kids[0], "name", "a template starts with its name");
        // name, declaration?, location*, init, transition*
        let first_transition = kids.iter().position(|k| *k == "transition").unwrap();
        let init_at = kids.iter().position(|k| *k == "init").unwrap();
        assert!(
            kids[..init_at]
                .iter()
                .skip(1)
                .all(|k| *k == "location" || *k == "declaration")
        );
        assert_eq!(first_transition, init_at + 1);
        assert!(kids[init_at + 1..].iter().all(|k| *k == "transition"));
        let name = child(t, "name").text().unwrap().to_string();
        let mut local = BTreeSet::new();
        let mut names = Vec::new();
        for l in elements(t).filter(|n| n.has_tag_name("location")) {
            let id = l.attribute("id").expect("a location has an id").to_string();
            assert!(ids.insert(id.clone()), "location id {id} is unique");
            local.insert(id);
            names.push(child(l, "name").text().unwrap().to_string());
            for label in elements(l).filter(|n| n.has_tag_name("label")) {
                assert_eq!(label.attribute("kind"), Some("invariant"));
            }
        }
        let init = child(t, "init").attribute("ref").unwrap();
        assert!(
            local.contains(init),
            "{name}: init refers to one of its locations"
        );
        for tr in elements(t).filter(|n| n.has_tag_name("transition")) {
            let s = child(tr, "source").attribute("ref").unwrap();
            let d = child(tr, "target").attribute("ref").unwrap();
            assert!(local.contains(s) && local.contains(d), "{name}: {s} -> {d}");
            for label in elements(tr).filter(|n| n.has_tag_name("label")) {
                let kind = label.attribute("kind").unwrap();
                assert!(
                    ["select", "guard", "synchronisation", "assignment"].contains(&kind),
                    "{kind}"
                );
                assert!(!label.text().unwrap_or("").trim().is_empty());
            }
        }
        out.insert(name, names);
    }
    let system = child(nta, "system").text().unwrap();
    assert!(system.contains("system Robot, Obstacle;"), "{system}");
    let formula = child(child(child(nta, "queries"), "query"), "formula");
    assert!(formula.text().unwrap().starts_with("A[] "));
    out
}

#[test]
fn xml_is_well_formed_with_the_seeds_automata() {
    let m = export(&seed(), "5");
    let locations = check_structure(&m.xml);
    assert_eq!(
        locations["Robot"],
        ["Idle", "Accelerate", "Drive", "Brake", "Stop"]
    );
    assert_eq!(locations["Obstacle"], ["Init", "Idle", "Move"]);
    assert!(
        m.xml
            .starts_with("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!DOCTYPE nta")
    );
}

#[test]
fn every_rule_and_latency_exports_a_well_formed_model() {
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in 0..=3 {
            for wab in [true, false] {
                let p = small(rule, latency, 0.3, wab, 1.0, 2.0);
                check_structure(&export(&p, "3").xml);
            }
        }
    }
}

/// UPPAAL's reserved keywords (docs.uppaal.org, "Reserved Keywords"), including those
/// reserved for future use.
const RESERVED: &[&str] = &[
    "chan",
    "clock",
    "double",
    "bool",
    "int",
    "commit",
    "const",
    "urgent",
    "broadcast",
    "init",
    "process",
    "state",
    "invariant",
    "location",
    "guard",
    "sync",
    "assign",
    "system",
    "trans",
    "deadlock",
    "and",
    "or",
    "not",
    "imply",
    "true",
    "false",
    "for",
    "forall",
    "exists",
    "while",
    "do",
    "if",
    "else",
    "return",
    "typedef",
    "struct",
    "rate",
    "before_update",
    "after_update",
    "meta",
    "priority",
    "progress",
    "scalar",
    "select",
    "void",
    "default",
    "string",
    "minE",
    "maxE",
    "Pr",
    "switch",
    "case",
    "continue",
    "break",
    "enum",
];

#[test]
fn no_identifier_is_a_reserved_keyword() {
    let m = export(&seed(), "5");
    let mut names: Vec<&str> = Vec::new();
    for d in &m.network.declarations {
        match d {
            Decl::Const { name, .. } | Decl::ConstArray { name, .. } | Decl::Var { name, .. } => {
                names.push(name)
            }
            Decl::Chans(c) => names.extend(c.iter().copied()),
            Decl::Func(f) => {
                names.push(f.name);
                names.extend(f.params.iter().copied());
                names.extend(f.locals.iter().copied());
            }
            _ => {}
        }
    }
    for t in &m.network.templates {
        names.push(t.name);
        names.extend(t.locations.iter().map(|l| l.name));
        names.extend(t.edges.iter().filter_map(|e| e.select.map(|s| s.0)));
    }
    assert!(names.len() > 40);
    for n in names {
        assert!(!RESERVED.contains(&n), "{n} is reserved in UPPAAL");
        assert!(
            n.chars().next().unwrap().is_ascii_alphabetic()
                && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
            "{n}"
        );
    }
}

fn declaration(m: &UppaalModel) -> String {
    uppaal::declarations_text(&m.network)
}

#[test]
fn declarations_write_out_the_guards_in_uppaals_language() {
    let m = export(&seed(), "5");
    let d = declaration(&m);
    for f in [
        "bool collisionDanger() {",
        "bool wrongAssumption() {",
        "bool inArea() {",
        "void endPeriod(int dx, int vEnd) {",
    ] {
        assert!(d.contains(f), "missing {f}");
    }
    // The paper's rule, multiplied out on the grid.
    assert!(d.contains("return inArea() && (observedGap() - BUFFER) * BRK <= v * v + VA * v;"));
    assert!(d.contains("return WRONG_ASSUMPTION_BRAKE && inArea() && observedFast();"));
    let kinematic = Problem {
        controller: Controller {
            danger_rule: DangerRule::Kinematic,
            ..seed().controller
        },
        ..seed()
    };
    assert!(
        declaration(&export(&kinematic, "5")).contains(
            "return inArea() && 2 * (observedGap() - BUFFER) * BRK <= v * v + 2 * VA * v;"
        )
    );
    let area = Problem {
        controller: Controller {
            danger_rule: DangerRule::Area,
            ..seed().controller
        },
        ..seed()
    };
    assert!(
        declaration(&export(&area, "5"))
            .contains("bool collisionDanger() {\n    return inArea();\n}")
    );
    check_lines(&d);
}

/// Balanced braces and parentheses; every statement line ends in ; { or }.
fn check_lines(d: &str) {
    assert_eq!(d.matches('{').count(), d.matches('}').count());
    assert_eq!(d.matches('(').count(), d.matches(')').count());
    for line in d.lines().map(str::trim) {
        if line.is_empty() || line.starts_with("//") {
            continue;
        }
        let code = line.split("  //").next().unwrap().trim_end();
        assert!(
            code.ends_with(';') || code.ends_with('{') || code.ends_with('}'),
            "{line}"
        );
    }
}

/// `const int NAME = value;` from the declarations.
fn constants(m: &UppaalModel) -> HashMap<String, i64> {
    let mut out = HashMap::new();
    for line in declaration(m).lines() {
        if let Some(rest) = line.strip_prefix("const int ")
            && let Some((name, value)) = rest.split_once(" = ")
            && !name.contains('[')
        {
            let value = value.split(';').next().unwrap();
            out.insert(name.to_string(), value.parse().unwrap());
        }
    }
    out
}

#[test]
fn the_scaling_is_stated_and_exact() {
    let p = seed();
    let m = export(&p, "5");
    let d = Exact::from(m.grid.scale.clone());
    assert_eq!(m.grid.scale, 4000u32.into(), "the seed's grid: 1/4000 m");
    assert!(
        m.xml.contains("1 unit = 1/4000 m"),
        "the scale is stated in an XML comment"
    );
    assert!(
        m.xml
            .contains("1 model time unit = 1 control period = 0.1 s")
    );
    assert!(m.xml.contains("nothing is rounded"));
    let c = constants(&m);
    let x = p.params::<Exact>();
    let on = |k: &str| Exact::from(c[k]) / d.clone();
    assert_eq!(on("G0"), x.g0);
    assert_eq!(on("VMAX"), x.v_max.clone() * x.dt.clone());
    assert_eq!(on("ACC"), x.a.clone() * x.dt.clone() * x.dt.clone());
    assert_eq!(on("BRK"), x.b.clone() * x.dt.clone() * x.dt.clone());
    assert_eq!(on("VA"), x.V_a.clone() * x.dt.clone());
    assert_eq!(on("BUFFER"), x.buffer);
    assert_eq!(on("CLEARANCE"), x.clearance);
    assert_eq!(c["L"], 1);
    assert_eq!(c["RHO"], 5600, "floor(1.4 * 4000)");
    let set = SpeedSet::parse("5", &x.W).unwrap();
    let wset: Vec<Exact> = m
        .grid
        .speeds
        .iter()
        .map(|&w| Exact::from(w) / d.clone())
        .collect();
    let want: Vec<Exact> = set
        .speeds()
        .iter()
        .map(|w| w.clone() * x.dt.clone())
        .collect();
    assert_eq!(wset, want);
    assert!(declaration(&m).contains("const int WSET[NW] = {0, 15, 30, 45, 60};"));
}

#[test]
fn the_query_file_states_passive_safety_and_the_seeds_form() {
    let m = export(&seed(), "5");
    let formula = "A[] not ((v > 0 && gap <= CLEARANCE) || (rested && restGap < CLEARANCE))";
    assert!(m.query.trim_end().ends_with(formula), "{}", m.query);
    assert!(m.query.starts_with("/*"));
    assert!(
        m.query
            .contains("A[] forall (i:int[0,N-1]) R.y == obstacles[i].y")
    );
    assert!(m.query.contains("A[] (gap <= CLEARANCE imply v == 0)"));
    assert_eq!(uppaal::query_formula(&m.network), formula);
}

// ---------------------------------------------------------------------------------------------
// Behaviour: the network answers what the explorer answers
// ---------------------------------------------------------------------------------------------

#[test]
fn the_network_agrees_with_the_explorer_on_the_same_finite_model() {
    let mut verdicts = BTreeSet::new();
    let mut cases = 0;
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in 0..=3 {
            for (w, wab, rho) in [(0.1, true, 0.6), (0.3, true, 0.3), (0.3, false, 1.0)] {
                let p = small(rule, latency, w, wab, rho, 1.2);
                let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
                let m = uppaal::export(&p, &set).unwrap();
                let g = uppaal::explore_grid(&m, &Options::default()).unwrap();
                let e = explore::explore(&p, set, &Options::default()).unwrap();
                let what = format!("{rule} L={latency} W={w} wab={wab} rho={rho}");
                assert!(g.complete, "{what}");
                assert_eq!(g.verdict, e.verdict, "{what}: verdict");
                assert_eq!(
                    g.collision_period,
                    e.counterexample.as_ref().map(|c| c.periods()),
                    "{what}: shortest path to a collision, in periods"
                );
                if e.verdict == ExploreVerdict::Safe {
                    assert_eq!(g.min_separation, e.min_separation, "{what}: separation");
                    let d = Exact::from(m.grid.scale.clone());
                    assert_eq!(
                        Exact::from(g.min_separation_grid.unwrap()) / d,
                        e.min_separation.clone().unwrap()
                    );
                }
                verdicts.insert(format!("{:?}", g.verdict));
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 36);
    assert_eq!(
        verdicts.len(),
        2,
        "both safe and colliding problems: {verdicts:?}"
    );
}

#[test]
fn the_seed_network_agrees_with_the_explorer() {
    let p = seed();
    let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
    let m = uppaal::export(&p, &set).unwrap();
    let g = uppaal::explore_grid(&m, &Options::default()).unwrap();
    let e = explore::explore(&p, set, &Options::default()).unwrap();
    assert_eq!(
        (g.verdict, e.verdict),
        (ExploreVerdict::Safe, ExploreVerdict::Safe)
    );
    assert_eq!(g.min_separation, e.min_separation);
    assert!(g.states > e.states, "the network has no state abstraction");
}

/// What the interpreter and the explorer answer on the same finite model, compared: the
/// verdict, the shortest collision period and (when safe) the minimum separation. Returns
/// the verdict.
fn agree(p: &Problem, speeds: &str, what: &str) -> ExploreVerdict {
    agree_from(p, speeds, explore::DEFAULT_STARTS, what)
}

/// [`agree`] with `starts` starts in a range of initial gaps.
fn agree_from(p: &Problem, speeds: &str, starts: usize, what: &str) -> ExploreVerdict {
    let set = SpeedSet::parse(speeds, &p.params::<Exact>().W).unwrap();
    let m = uppaal::export_with_starts(p, &set, starts).unwrap_or_else(|e| panic!("{what}: {e}"));
    let g = uppaal::explore_grid(&m, &Options::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
    let model = explore::FiniteModel::new(p, set)
        .with_starts(starts)
        .unwrap();
    let e = explore::explore_model(&model, &Options::default()).unwrap();
    assert_eq!(m.grid.starts.len(), e.starts.len(), "{what}: starts");
    assert!(g.complete && e.complete, "{what}");
    assert_eq!(g.verdict, e.verdict, "{what}: verdict");
    assert_eq!(
        g.collision_period,
        e.counterexample.as_ref().map(|c| c.periods()),
        "{what}: shortest path to a collision, in periods"
    );
    if e.verdict == ExploreVerdict::Safe {
        assert_eq!(g.min_separation, e.min_separation, "{what}: separation");
    }
    g.verdict
}

/// The small problems of the agreement tests, with `change` applied: every danger rule,
/// latencies 0–2, W below V_a (guard active) and above it (with and without the guard).
fn sweep(change: impl Fn(&mut Problem), label: &str) -> BTreeSet<String> {
    let mut verdicts = BTreeSet::new();
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in 0..=2 {
            for (w, wab, rho) in [(0.1, true, 0.6), (0.3, true, 0.3), (0.3, false, 1.0)] {
                let mut p = small(rule, latency, w, wab, rho, 1.2);
                change(&mut p);
                p.validate("uppaal-test").expect("a valid test problem");
                let what = format!("{label}: {rule} L={latency} W={w} wab={wab} rho={rho}");
                verdicts.insert(format!("{:?}", agree(&p, "3", &what)));
            }
        }
    }
    verdicts
}

#[test]
fn weaker_brakes_and_a_moving_start_agree_with_the_explorer() {
    let weaker = sweep(|p| p.robot.braking_min = Some(0.3), "braking_min 0.3");
    let moving = sweep(|p| p.robot.initial_speed = Some(0.2), "initial_speed 0.2");
    let cruising = sweep(
        |p| {
            p.robot.initial_speed = Some(0.4);
            p.robot.braking_min = Some(0.4);
        },
        "initial_speed v_max, braking_min 0.4",
    );
    for v in [weaker, moving, cruising] {
        assert_eq!(v.len(), 2, "both safe and colliding problems: {v:?}");
    }
}

#[test]
fn weaker_brakes_and_a_moving_start_are_declared_and_used() {
    let mut p = small(DangerRule::Kinematic, 1, 0.1, true, 0.6, 1.2);
    p.robot.braking_min = Some(0.3);
    p.robot.initial_speed = Some(0.2);
    let m = export(&p, "3");
    let c = constants(&m);
    let d = Exact::from(m.grid.scale.clone());
    let x = p.params::<Exact>();
    let on = |k: &str| Exact::from(c[k]) / d.clone();
    assert_eq!(on("BRK"), x.b.clone() * x.dt.clone() * x.dt.clone());
    assert_eq!(on("BRKMIN"), x.b_min.clone() * x.dt.clone() * x.dt.clone());
    assert_eq!(on("V0"), x.v0.clone() * x.dt.clone());
    let text = declaration(&m);
    check_lines(&text);
    // The controller's b in the danger distance, the plant's b_min in the motion.
    assert!(text.contains("2 * (observedGap() - BUFFER) * BRK <= v * v + 2 * VA * v;"));
    assert!(
        text.contains("endPeriod(v - BRKMIN / 2, v - BRKMIN);"),
        "{text}"
    );
    assert!(text.contains("v = V0;"));
    check_structure(&m.xml);
    // At top speed the robot starts in Drive.
    p.robot.initial_speed = Some(0.4);
    let m = export(&p, "3");
    let robot = &m.network.templates[0];
    assert_eq!(robot.locations[robot.edges[0].target].name, "Drive");
    // Without them, neither constant is written: the seed's file is unchanged.
    let plain = declaration(&export(&seed(), "5"));
    assert!(!plain.contains("BRKMIN") && !plain.contains("V0"));
}

#[test]
fn ranges_of_initial_gaps_agree_with_the_explorer() {
    // Every start of the range one period's travel apart and less: the alignment with the
    // control period differs between starts.
    let range = sweep(
        |p| p.environment.initial_gap = Position::Range(1.0, 1.4),
        "initial_gap [1.0, 1.4]",
    );
    assert_eq!(
        range.len(),
        2,
        "both safe and colliding problems: {range:?}"
    );
    // Other start counts, with the other settings.
    for (starts, lo, hi) in [(2, 0.9, 1.3), (3, 1.0, 1.1), (7, 0.8, 1.6)] {
        let mut p = small(DangerRule::Kinematic, 1, 0.1, true, 0.6, 1.2);
        p.environment.initial_gap = Position::Range(lo, hi);
        p.robot.braking_min = Some(0.3);
        p.robot.initial_speed = Some(0.1);
        let what = format!("--starts {starts} in [{lo}, {hi}]");
        agree_from(&p, "3", starts, &what);
    }
}

#[test]
fn a_range_is_declared_as_the_explorers_starts() {
    let mut p = small(DangerRule::Paper, 1, 0.1, true, 0.6, 1.2);
    p.environment.initial_gap = Position::Range(1.0, 1.3);
    let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
    let m = uppaal::export_with_starts(&p, &set, 4).unwrap();
    let d = Exact::from(m.grid.scale.clone());
    let model = explore::FiniteModel::new(&p, set).with_starts(4).unwrap();
    let on_grid: Vec<Exact> = m
        .grid
        .starts
        .iter()
        .map(|&g| Exact::from(g) / d.clone())
        .collect();
    assert_eq!(on_grid, model.starts());
    let c = constants(&m);
    assert_eq!(c["NSTART"], 4);
    assert_eq!(c["G0MAX"], *m.grid.starts.last().unwrap());
    assert!(!c.contains_key("G0"));
    let text = declaration(&m);
    check_lines(&text);
    assert!(text.contains("const int GSTART[NSTART] = {"), "{text}");
    assert!(text.contains("void initialise(int g0) {"), "{text}");
    assert!(text.contains("int[GMIN,G0MAX] gap"), "{text}");
    check_structure(&m.xml);
    assert!(
        m.xml.contains("s : int[0, NSTART - 1]"),
        "the start is a select"
    );
    assert!(m.xml.contains("initialise(GSTART[s])"));
    assert!(m.xml.contains("--starts 4"));
    // Bad start counts are refused as the explorer refuses them.
    let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
    let err = uppaal::export_with_starts(&p, &set, 1).unwrap_err();
    assert!(matches!(err, UppaalError::Options(_)), "{err}");
}

#[test]
fn cli_exports_and_explores_a_range_as_the_explorers_starts() {
    let dir = tmp();
    let problem = dir.path().join("range.toml");
    let mut p = small(DangerRule::Paper, 1, 0.1, true, 1.0, 1.2);
    p.environment.initial_gap = Position::Range(1.0, 1.3);
    p.robot.braking_min = Some(0.4);
    std::fs::write(&problem, p.to_toml_string()).unwrap();
    safereach(dir.path())
        .arg("export-uppaal")
        .arg(&problem)
        .args(["--speeds", "3", "--starts", "3", "--out", "range.xml"])
        .assert()
        .code(0);
    let xml = std::fs::read_to_string(dir.path().join("range.xml")).unwrap();
    let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
    assert_eq!(xml, uppaal::export_with_starts(&p, &set, 3).unwrap().xml);
    let json = |grid: bool| -> serde_json::Value {
        let mut cmd = safereach(dir.path());
        cmd.arg("explore")
            .arg(&problem)
            .args(["--speeds", "3", "--starts", "3", "--json"]);
        if grid {
            cmd.arg("--grid");
        }
        let out = cmd.assert().get_output().clone();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let (g, e) = (json(true), json(false));
    assert_eq!(g["grid"], true);
    assert_eq!(g["verdict"], "safe");
    assert_eq!(g["verdict"], e["verdict"]);
    assert_eq!(g["min_separation"], e["min_separation"]);
}

fn sensing(p: &mut Problem, sg: f64, sw: f64) {
    p.sensing = Some(Sensing {
        gap_noise: Some(sg),
        speed_noise: Some(sw),
        first_detection_gap: None,
    });
}

#[test]
fn sensing_noise_agrees_with_the_explorer() {
    for (sg, sw) in [(0.05, 0.0), (0.0, 0.15), (0.2, 0.05), (0.03, 0.12)] {
        let label = format!("gap_noise {sg}, speed_noise {sw}");
        let v = sweep(|p| sensing(p, sg, sw), &label);
        assert_eq!(
            v.len(),
            2,
            "{label}: both safe and colliding problems: {v:?}"
        );
    }
    // With the other settings, and with no buffer (d_coll from 0 at rest).
    let v = sweep(
        |p| {
            sensing(p, 0.05, 0.1);
            p.robot.braking_min = Some(0.3);
            p.robot.initial_speed = Some(0.2);
            p.controller.buffer = 0.0;
        },
        "noise, b_min, v0, no buffer",
    );
    assert!(!v.is_empty());
}

#[test]
fn sensing_noise_is_declared_and_selected_on_the_decide_edge() {
    let mut p = small(DangerRule::Paper, 1, 0.1, true, 0.6, 1.2);
    sensing(&mut p, 0.05, 0.15);
    let m = export(&p, "3");
    let c = constants(&m);
    let d = Exact::from(m.grid.scale.clone());
    let x = p.params::<Exact>();
    assert_eq!(Exact::from(c["SG"]) / d.clone(), x.sigma_g);
    assert_eq!(Exact::from(c["SW"]) / d, x.sigma_w.clone() * x.dt.clone());
    let text = declaration(&m);
    check_lines(&text);
    for f in [
        "int observedGap(int e) {",
        "bool observedFast(int e) {",
        "bool collisionDanger(int e) {",
        "bool wrongAssumption(int e) {",
        "fastAt[0] = w + SW > VA;",
        "slowAt[0] = w - SW <= VA;",
    ] {
        assert!(text.contains(f), "missing {f}:\n{text}");
    }
    check_structure(&m.xml);
    assert!(m.xml.contains("e : int[0, 5]"));
    assert!(
        m.xml
            .contains("!(collisionDanger(e) || wrongAssumption(e))")
    );
}

/// With gap noise every positive guard threshold is at least one grid unit (the grid is
/// refined if need be), so that an integer observed gap fires whenever a real one can.
#[test]
fn gap_noise_refines_the_grid_to_whole_unit_thresholds() {
    let mut p = small(DangerRule::Area, 0, 0.1, true, 0.0001, 1.2);
    let plain = export(&p, "3");
    assert_eq!(
        plain.grid.rho, 0,
        "without noise rho need not be a whole unit"
    );
    sensing(&mut p, 0.05, 0.0);
    let m = export(&p, "3");
    assert!(m.grid.rho >= 1, "rho is {} units", m.grid.rho);
    assert_eq!(
        m.grid.scale.clone() % plain.grid.scale.clone(),
        0u8.into(),
        "a refinement of the plain grid"
    );
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in 0..=1 {
            let mut q = small(rule, latency, 0.1, true, 0.0001, 1.2);
            sensing(&mut q, 0.05, 0.0);
            agree(&q, "3", &format!("tiny rho, {rule} L={latency}"));
        }
    }
}

/// With noise, errors that realise only part of the guard outcomes (the gap seen only at
/// the ends of its interval, the speed never off) answer differently from the explorer.
#[test]
fn too_few_observation_errors_are_caught() {
    let mut caught = 0;
    for rule in [DangerRule::Paper, DangerRule::Area] {
        for latency in 0..=1 {
            for (w, wab, rho) in [(0.1, true, 0.6), (0.3, true, 0.3)] {
                let mut p = small(rule, latency, w, wab, rho, 1.2);
                sensing(&mut p, 0.2, 0.15);
                let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
                let mut m = uppaal::export(&p, &set).unwrap();
                for e in &mut m.network.templates[0].edges {
                    if let Some(sel) = &mut e.select {
                        sel.2 = 1;
                    }
                }
                let g = uppaal::explore_grid(&m, &Options::default()).unwrap();
                let e = explore::explore(&p, set, &Options::default()).unwrap();
                if (g.verdict, g.collision_period, g.min_separation)
                    != (
                        e.verdict,
                        e.counterexample.as_ref().map(|c| c.periods()),
                        e.min_separation.clone(),
                    )
                {
                    caught += 1;
                }
            }
        }
    }
    assert!(caught > 0, "too few errors went unnoticed");
}

fn occlusion(p: &mut Problem, d_det: f64, sg: f64, sw: f64) {
    p.sensing = Some(Sensing {
        gap_noise: Some(sg),
        speed_noise: Some(sw),
        first_detection_gap: Some(d_det),
    });
}

#[test]
fn occlusion_agrees_with_the_explorer() {
    for d_det in [0.25, 0.5, 0.9] {
        let label = format!("first_detection_gap {d_det}");
        let v = sweep(|p| occlusion(p, d_det, 0.0, 0.0), &label);
        assert_eq!(
            v.len(),
            2,
            "{label}: both safe and colliding problems: {v:?}"
        );
    }
    // With noise, b_min and a moving start.
    let v = sweep(
        |p| {
            occlusion(p, 0.5, 0.05, 0.15);
            p.robot.braking_min = Some(0.3);
            p.robot.initial_speed = Some(0.2);
        },
        "occlusion with noise, b_min, v0",
    );
    assert!(!v.is_empty());
    // A start below d_det has no behaviour at all.
    let mut p = small(DangerRule::Paper, 1, 0.1, true, 1.0, 1.2);
    occlusion(&mut p, 1.5, 0.0, 0.0);
    assert_eq!(agree(&p, "3", "never seen"), ExploreVerdict::Safe);
}

#[test]
fn occlusion_is_declared_and_used() {
    let mut p = small(DangerRule::Paper, 0, 0.1, true, 1.0, 1.2);
    occlusion(&mut p, 0.5, 0.0, 0.0);
    let m = export(&p, "3");
    let c = constants(&m);
    let d = Exact::from(m.grid.scale.clone());
    assert_eq!(Exact::from(c["DDET"]) / d, Exact::from(1) / Exact::from(2));
    let text = declaration(&m);
    check_lines(&text);
    for f in [
        "bool seen = false;",
        "bool shown() {",
        "bool lostAfter(int dx) {",
        "return !seen && gap - dx - w < DDET;",
    ] {
        assert!(text.contains(f), "missing {f}:\n{text}");
    }
    check_structure(&m.xml);
    assert!(
        m.xml.contains("G0 &gt;= DDET"),
        "a start below DDET is no behaviour"
    );
    assert!(m.xml.contains("!lostAfter(VMAX)"));
    p.robot.latency = 2;
    let text = declaration(&export(&p, "3"));
    assert!(
        text.contains("return !seen && gapAt[L - 1] < DDET;"),
        "{text}"
    );
}

/// A network that lets the hidden obstacle stay hidden for good (no lost behaviours cut)
/// answers differently from the explorer.
#[test]
fn hiding_the_obstacle_for_good_is_caught() {
    let mut caught = 0;
    for rule in [DangerRule::Paper, DangerRule::Area] {
        for latency in 0..=2 {
            let mut p = small(rule, latency, 0.1, true, 1.0, 1.2);
            occlusion(&mut p, 0.5, 0.0, 0.0);
            let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
            let m = uppaal::export(&p, &set).unwrap();
            let broken = with_decl(&m, |d| {
                if let Decl::Func(f) = d
                    && f.name == "lostAfter"
                {
                    f.body = vec![uppaal::Stmt::Return(uppaal::Expr::Bool(false))];
                }
            });
            let g = uppaal::explore_grid(&broken, &Options::default()).unwrap();
            let e = explore::explore(&p, set, &Options::default()).unwrap();
            if (g.verdict, g.collision_period) != (e.verdict, e.counterexample.map(|c| c.periods()))
            {
                caught += 1;
            }
        }
    }
    assert!(caught > 0, "hiding for good went unnoticed");
}

/// The settings above over more speeds and latencies, each alone and combined (a larger
/// sweep: run with `--ignored`).
#[test]
#[ignore = "a larger sweep (about 70 s in release)"]
fn the_real_sensors_settings_agree_with_the_explorer_over_more_speeds() {
    type Change = fn(&mut Problem);
    let changes: [(&str, Change); 5] = [
        ("b_min, v0", |p| {
            p.robot.braking_min = Some(0.25);
            p.robot.initial_speed = Some(0.3);
        }),
        ("range", |p| {
            p.environment.initial_gap = Position::Range(0.9, 1.5)
        }),
        ("noise", |p| sensing(p, 0.1, 0.1)),
        ("occlusion", |p| occlusion(p, 0.7, 0.0, 0.0)),
        ("all but the range", |p| {
            p.robot.braking_min = Some(0.25);
            p.robot.initial_speed = Some(0.1);
            occlusion(p, 0.4, 0.03, 0.12);
        }),
    ];
    for (label, change) in changes {
        for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
            for latency in 0..=3 {
                for (w, wab, rho) in [(0.1, true, 0.6), (0.3, true, 0.3), (0.3, false, 1.0)] {
                    let mut p = small(rule, latency, w, wab, rho, 1.2);
                    change(&mut p);
                    p.validate("uppaal-test").expect("a valid test problem");
                    let what = format!("{label}: {rule} L={latency} W={w} wab={wab} rho={rho}");
                    agree(&p, "4", &what);
                }
            }
        }
    }
}

/// A network whose danger distance used the plant's b_min instead of the controller's b
/// would answer differently from the explorer: the comparison catches it.
#[test]
fn a_danger_distance_with_the_plants_braking_is_caught() {
    let mut caught = 0;
    for rule in [DangerRule::Paper, DangerRule::Kinematic] {
        for latency in 0..=2 {
            let mut p = small(rule, latency, 0.1, true, 1.0, 1.2);
            p.robot.braking_min = Some(0.2);
            let set = SpeedSet::parse("3", &p.params::<Exact>().W).unwrap();
            let m = uppaal::export(&p, &set).unwrap();
            let broken = with_decl(&m, |d| {
                if let Decl::Func(f) = d
                    && f.name == "collisionDanger"
                {
                    let text = format!("{:?}", f.body);
                    assert!(text.contains("Name(\"BRK\")"), "{text}");
                    f.body = rename(&f.body, "BRK", "BRKMIN");
                }
            });
            let g = uppaal::explore_grid(&broken, &Options::default()).unwrap();
            let e = explore::explore(&p, set, &Options::default()).unwrap();
            if (g.verdict, g.collision_period, g.min_separation)
                != (
                    e.verdict,
                    e.counterexample.as_ref().map(|c| c.periods()),
                    e.min_separation.clone(),
                )
            {
                caught += 1;
            }
        }
    }
    assert!(caught > 0, "the broken danger distance went unnoticed");
}

/// `stmts` with every use of the name `from` replaced by `to`.
fn rename(stmts: &[uppaal::Stmt], from: &str, to: &'static str) -> Vec<uppaal::Stmt> {
    use uppaal::{Expr, Stmt};
    fn expr(e: &Expr, from: &str, to: &'static str) -> Expr {
        match e {
            Expr::Name(x) if *x == from => Expr::Name(to),
            Expr::Elem(a, i) => Expr::Elem(a, Box::new(expr(i, from, to))),
            Expr::Call(f, args) => Expr::Call(f, args.iter().map(|a| expr(a, from, to)).collect()),
            Expr::Not(a) => Expr::Not(Box::new(expr(a, from, to))),
            Expr::Bin(op, a, b) => Expr::Bin(
                *op,
                Box::new(expr(a, from, to)),
                Box::new(expr(b, from, to)),
            ),
            other => other.clone(),
        }
    }
    stmts
        .iter()
        .map(|s| match s {
            Stmt::Return(e) => Stmt::Return(expr(e, from, to)),
            other => other.clone(),
        })
        .collect()
}

fn with_decl(m: &UppaalModel, change: impl Fn(&mut Decl)) -> UppaalModel {
    let mut m = m.clone();
    for d in &mut m.network.declarations {
        change(d);
    }
    m
}

/// The interpreter is a checker: a range too narrow for the reachable gaps is UPPAAL's abort,
/// and a grid that would make a division round is an error, not a silent rounding.
#[test]
fn the_interpreter_catches_broken_networks() {
    let p = small(DangerRule::Paper, 1, 0.3, true, 0.3, 1.2);
    let m = export(&p, "2");
    assert!(uppaal::explore_grid(&m, &Options::default()).is_ok());
    let narrow = with_decl(&m, |d| {
        if let Decl::Var {
            name: "gap",
            range: Some(r),
            ..
        } = d
        {
            r.3 -= 1;
        }
    });
    let err = uppaal::explore_grid(&narrow, &Options::default()).unwrap_err();
    assert!(
        matches!(&err, UppaalError::Run(m) if m.contains("outside its declared range")),
        "{err}"
    );
    let odd = with_decl(&m, |d| {
        if let Decl::Const {
            name: "ACC", value, ..
        } = d
        {
            *value += 1;
        }
    });
    let err = uppaal::explore_grid(&odd, &Options::default()).unwrap_err();
    assert!(
        matches!(&err, UppaalError::Run(m) if m.contains("not exact")),
        "{err}"
    );
    let budget = uppaal::explore_grid(
        &m,
        &Options {
            max_states: 10,
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(budget.verdict, ExploreVerdict::Inconclusive);
}

#[test]
fn grids_beyond_32_bits_are_refused() {
    let p = seed();
    let set = SpeedSet::parse("1/7919,1/7907,1/7901,0.15", &p.params::<Exact>().W).unwrap();
    let err = uppaal::export(&p, &set).unwrap_err();
    assert!(matches!(err, UppaalError::Grid(_)), "{err}");
    assert!(err.to_string().contains("32-bit"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// The command
// ---------------------------------------------------------------------------------------------

#[test]
fn cli_writes_the_model_and_the_query_beside_it() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("export-uppaal")
        .arg(problem_file("seed.toml"))
        .args(["--out", "seed.xml"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(text.contains("1 distance unit = 1/4000 m"), "{text}");
    assert_eq!(
        files(dir.path()),
        BTreeSet::from(["seed.q".into(), "seed.xml".into()])
    );
    let xml = std::fs::read_to_string(dir.path().join("seed.xml")).unwrap();
    assert_eq!(xml, export(&seed(), "5").xml);
    check_structure(&xml);
    let q = std::fs::read_to_string(dir.path().join("seed.q")).unwrap();
    assert!(q.contains("A[] not"));
    // Default name: the problem's, in the current directory.
    let other = tmp();
    safereach(other.path())
        .arg("export-uppaal")
        .arg(problem_file("static-obstacle.toml"))
        .args(["--speeds", "2"])
        .assert()
        .code(0);
    assert_eq!(
        files(other.path()),
        BTreeSet::from(["static-obstacle.q".into(), "static-obstacle.xml".into()])
    );
}

#[test]
fn cli_bad_input_exits_2() {
    let dir = tmp();
    let cases = [
        (vec!["--out", "model.q"], "must not end in .q"),
        (vec!["--speeds", "0.9"], "outside [0, W]"),
        (vec!["--speeds", "1/7919,1/7907,1/7901,0.15"], "32-bit"),
        (vec!["--out", "missing-dir/seed.xml"], "missing-dir"),
    ];
    bad_input_exits_2(dir.path(), "export-uppaal", &seed_file(), &cases);
    assert!(files(dir.path()).is_empty(), "nothing written on error");
}

#[test]
fn cli_explore_grid_answers_like_the_explorer() {
    let dir = tmp();
    let grid = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "2", "--grid", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let plain = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "2", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let g: serde_json::Value = serde_json::from_slice(&grid.stdout).unwrap();
    let e: serde_json::Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert_eq!(g["verdict"], "safe");
    assert_eq!(g["grid"], true);
    assert_eq!(g["min_separation"], e["min_separation"]);
    assert_eq!(g["scale_per_metre"], "4000");
}
