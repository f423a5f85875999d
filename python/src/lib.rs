//! Python bindings of safereach: a thin layer over the library (problems, certify, check,
//! radius, largest safe speed and the runtime monitor). Every answer is the library's; a
//! certificate handed to Python has passed the exact `check`.

use numpy::PyReadonlyArray1;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

use safereach::analysis::planar::{
    BoundaryError, KnobError, certify_text, max_speed_search, safe_radius_search,
};
use safereach::analysis::region_search::{
    DEFAULT_DEPTH, PLANAR_DEFAULT_DEPTH, RegionOptions, map_planar_region, map_region,
    map_scene_region,
};
use safereach::analysis::scene_answer::SceneAnswer;
use safereach::analysis::{self, radius};
use safereach::core::model::Problem as LibProblem;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::planar::PlanarProblem;
use safereach::core::scene::Scene;
use safereach::core::semantics::Mode;
use safereach::monitor::bag::{BagOptions, BagReader, LaneAxis, SpeedSource};
use safereach::monitor::planar::{
    PlanarMonitor as LibPlanarMonitor, PlanarRobotSample, PlanarSample,
};
use safereach::monitor::{Monitor as LibMonitor, Sample};
use safereach::proof::certificate::Certificate as LibCertificate;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::RegionMap as LibRegionMap;

create_exception!(
    _safereach,
    InputError,
    PyValueError,
    "A problem, key, value or certificate text that cannot be read; the message names the file or key and the reason, as the command line does."
);
create_exception!(
    _safereach,
    CertificateError,
    PyValueError,
    "A certificate that check rejects, or one a monitor cannot use; the message says why."
);
create_exception!(
    _safereach,
    AnalysisError,
    PyRuntimeError,
    "An analysis that could not be completed (a budget, the solver); never a verdict."
);

/// A problem as read: a single-obstacle problem, a scene, or a planar problem.
#[derive(Clone)]
enum Input {
    Problem(LibProblem),
    Scene(Scene),
    Planar(Box<PlanarProblem>),
}

/// Reads `text` with `sets` as the command line reads a file: a planar problem when it has a
/// `[plane]` table, else a problem if it is one (a range of initial gaps is answered as its
/// scene), else a scene; when neither reads, the scene reader's error for a file in scene
/// form, else the problem reader's.
fn read(text: &str, origin: &str, sets: &[String]) -> PyResult<Input> {
    if PlanarProblem::is_planar(text) {
        return PlanarProblem::from_toml_str_with_overrides(text, origin, sets)
            .map(|p| Input::Planar(Box::new(p)))
            .map_err(|e| InputError::new_err(e.to_string()));
    }
    let problem_error = match LibProblem::from_toml_str_with_overrides(text, origin, sets) {
        Ok(p) if p.environment.initial_gap.is_range() => {
            return Ok(Input::Scene(Scene::from_problem(&p)));
        }
        Ok(p) => return Ok(Input::Problem(p)),
        Err(e) => e,
    };
    match Scene::from_toml_str_with_overrides(text, origin, sets) {
        Ok(s) => Ok(Input::Scene(s)),
        Err(e) if scene_form(text) => Err(InputError::new_err(e.to_string())),
        Err(_) => Err(InputError::new_err(problem_error.to_string())),
    }
}

fn scene_form(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("scene") || t.contains_key("obstacle"))
}

/// A verification problem (TOML), with `--set`-style overrides.
#[pyclass(module = "safereach")]
#[derive(Clone)]
struct Problem {
    text: String,
    origin: String,
    sets: Vec<String>,
    input: Input,
}

#[pymethods]
impl Problem {
    /// Reads a problem or scene from TOML text; `origin` names it in error messages.
    #[new]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn new(text: &str, origin: &str) -> PyResult<Self> {
        let input = read(text, origin, &[])?;
        Ok(Problem {
            text: text.to_string(),
            origin: origin.to_string(),
            sets: Vec::new(),
            input,
        })
    }

    /// Reads the problem or scene file at `path`.
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Self> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(&path)
            .map_err(|e| InputError::new_err(format!("{origin}: {e}")))?;
        Self::new(&text, &origin)
    }

    /// Reads a problem from JSON text of the same keys as the TOML (used by `from_dict`).
    #[staticmethod]
    #[pyo3(signature = (json, origin = "<dict>"))]
    fn from_json(json: &str, origin: &str) -> PyResult<Self> {
        let value: toml::Value = serde_json::from_str(json)
            .map_err(|e| InputError::new_err(format!("{origin}: {e}")))?;
        let text =
            toml::to_string(&value).map_err(|e| InputError::new_err(format!("{origin}: {e}")))?;
        Self::new(&text, origin)
    }

    /// Overrides `key` (dotted, as `--set key=value`) with `value`; the problem is read again
    /// with every override so far, and left unchanged if the result is invalid.
    fn set(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let set = format!("{key}={}", toml_value(value)?);
        let mut sets = self.sets.clone();
        sets.push(set);
        self.input = read(&self.text, &self.origin, &sets)?;
        self.sets = sets;
        Ok(())
    }

    /// The problem's name.
    #[getter]
    fn name(&self) -> String {
        match &self.input {
            Input::Problem(p) => p.name.clone(),
            Input::Scene(s) => s.name.clone(),
            Input::Planar(p) => p.name.clone(),
        }
    }

    /// Whether it is a planar problem (obstacles from any direction, docs/semantics.md §13).
    #[getter]
    fn is_planar(&self) -> bool {
        matches!(self.input, Input::Planar(_))
    }

    /// Whether it is a scene (several obstacles or lanes) rather than one obstacle.
    #[getter]
    fn is_scene(&self) -> bool {
        matches!(self.input, Input::Scene(_))
    }

    /// The problem as JSON text (every key, overrides applied; a planar problem: the keys its
    /// text states, overrides applied).
    fn to_json(&self) -> PyResult<String> {
        Ok(match &self.input {
            Input::Problem(p) => serde_json::to_string(p),
            Input::Scene(s) => serde_json::to_string(s),
            Input::Planar(_) => serde_json::to_string(
                &PlanarProblem::stated_table(&self.text, &self.origin, &self.sets)
                    .map_err(|e| InputError::new_err(e.to_string()))?,
            ),
        }
        .expect("problems serialise"))
    }

    fn __repr__(&self) -> String {
        let kind = match self.input {
            Input::Problem(_) => "problem",
            Input::Scene(_) => "scene",
            Input::Planar(_) => "planar problem",
        };
        format!("<safereach.Problem {kind} {:?}>", self.name())
    }
}

/// A Python value as a TOML value for an override.
fn toml_value(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(b) = value.extract::<bool>() {
        return Ok(b.to_string());
    }
    if let Ok(i) = value.extract::<i64>() {
        return Ok(i.to_string());
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(format!("{x:?}"));
    }
    if let Ok(s) = value.extract::<String>() {
        return Ok(toml::Value::String(s).to_string());
    }
    if let Ok(items) = value.cast::<PyList>() {
        let parts: PyResult<Vec<String>> = items.iter().map(|x| toml_value(&x)).collect();
        return Ok(format!("[{}]", parts?.join(", ")));
    }
    Err(InputError::new_err(format!(
        "a value must be a number, a bool, a string or a list, not {}",
        value.get_type().name()?
    )))
}

/// A certificate: the verdict and what proves it, checked in exact arithmetic.
#[pyclass(module = "safereach")]
#[derive(Clone)]
struct Certificate {
    file: CertificateFile,
    json: Value,
}

impl Certificate {
    fn of(file: CertificateFile) -> Self {
        let json = serde_json::from_str(&file.to_json()).expect("certificates serialise");
        Certificate { file, json }
    }

    fn field(&self, py: Python<'_>, key: &str) -> PyResult<Py<PyAny>> {
        to_py(py, self.json.get(key).unwrap_or(&Value::Null))
    }
}

#[pymethods]
impl Certificate {
    /// Reads certificate JSON (as `certify --out` writes it); it is not checked until `check`.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        let file = CertificateFile::from_json(text)
            .map_err(|e| InputError::new_err(format!("certificate: {e}")))?;
        Ok(Certificate::of(file))
    }

    /// `certified`, `refuted` or `inconclusive`.
    #[getter]
    fn verdict(&self) -> &'static str {
        self.file.verdict().as_str()
    }

    /// s*, the worst-case minimum separation (m); None when it is -inf or not pinned.
    #[getter]
    fn min_separation(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.field(py, "min_separation")
    }

    /// The rigorous lower bound on s* (m), rounded down; None when not every part is proved.
    #[getter]
    fn lower_bound(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.field(py, "lower_bound")
    }

    /// The premises the verdict rests on: dicts with name, description, bound, unit.
    #[getter]
    fn premises(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.field(py, "premises")
    }

    /// The worst-case behaviour (speed and mode segments), as a dict; None when absent.
    #[getter]
    fn witness(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.field(py, "witness")
    }

    /// The whole certificate as a dict (the JSON object).
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(py, &self.json)
    }

    /// The certificate as JSON text, exactly as `certify --out` writes it.
    fn to_json(&self) -> String {
        self.file.to_json()
    }

    fn __repr__(&self) -> String {
        format!("<safereach.Certificate {}>", self.verdict())
    }
}

/// A JSON value as Python objects.
fn to_py(py: Python<'_>, v: &Value) -> PyResult<Py<PyAny>> {
    Ok(match v {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any().unbind(),
            (None, Some(x)) => x.into_pyobject(py)?.into_any().unbind(),
            _ => py.None(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for x in items {
                list.append(to_py(py, x)?)?;
            }
            list.into_any().unbind()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, x) in map {
                dict.set_item(k, to_py(py, x)?)?;
            }
            dict.into_any().unbind()
        }
    })
}

/// Certifies or refutes `problem`. The certificate has passed `check` (exact, no solver)
/// before it is returned. The GIL is released while the analysis runs.
#[pyfunction]
fn certify(py: Python<'_>, problem: &Problem) -> PyResult<Certificate> {
    let input = problem.input.clone();
    let (text, origin, sets) = (
        problem.text.clone(),
        problem.origin.clone(),
        problem.sets.clone(),
    );
    let file = py.detach(move || -> Result<CertificateFile, String> {
        let file = match &input {
            Input::Problem(p) => {
                let a = analysis::analyse(p).map_err(|e| e.to_string())?;
                CertificateFile::Single(Box::new(LibCertificate::from_analysis(&a)))
            }
            Input::Scene(s) => SceneAnswer::of(s).map_err(|e| e.to_string())?.certificate(),
            // The planar certificate carries the problem's text and overrides.
            Input::Planar(_) => {
                let (_, cert) = certify_text(&text, &origin, &sets).map_err(|e| e.to_string())?;
                CertificateFile::Planar(Box::new(cert))
            }
        };
        file.check()
            .map_err(|e| format!("internal error: the certificate does not verify: {e}"))?;
        Ok(file)
    });
    file.map(Certificate::of).map_err(AnalysisError::new_err)
}

/// Re-verifies `certificate` in exact arithmetic, without the solver; returns its verdict,
/// or raises CertificateError with the reason it is not valid.
#[pyfunction]
fn check(py: Python<'_>, certificate: &Certificate) -> PyResult<&'static str> {
    let file = certificate.file.clone();
    py.detach(move || file.check().map(|r| r.verdict.as_str()))
        .map_err(|e| CertificateError::new_err(e.to_string()))
}

/// The single-obstacle problem of `problem`, or an InputError naming what is needed.
fn single(problem: &Problem, what: &str) -> PyResult<LibProblem> {
    match &problem.input {
        Input::Problem(p) => Ok(p.clone()),
        Input::Scene(_) => Err(InputError::new_err(format!(
            "{what} takes a single-obstacle problem; for a scene use `safereach radius` / `sweep`"
        ))),
        Input::Planar(_) => Err(InputError::new_err(format!(
            "{what} takes a single-obstacle problem on the line; for a planar problem use \
             `safereach radius` / `max-speed` (a bisection of planar certifications)"
        ))),
    }
}

/// A planar search's error as Python sees it: a bad request or problem is an InputError,
/// a probe that could not be answered an AnalysisError.
fn knob_error(e: KnobError) -> PyErr {
    match e {
        KnobError::Input(why) => InputError::new_err(why),
        KnobError::Probe(BoundaryError::Problem(p)) => InputError::new_err(p.to_string()),
        KnobError::Probe(other) => AnalysisError::new_err(other.to_string()),
    }
}

/// The smallest certified reaction radius (m) at the problem's obstacle speed, or for each
/// of `speeds` (then a list); None where no radius certifies.
#[pyfunction]
#[pyo3(signature = (problem, speeds = None))]
fn safe_radius(py: Python<'_>, problem: &Problem, speeds: Option<Vec<f64>>) -> PyResult<Py<PyAny>> {
    if let Input::Planar(base) = &problem.input {
        let list = speeds.is_some();
        let speeds: Vec<Option<f64>> = match speeds {
            Some(ws) => ws.into_iter().map(Some).collect(),
            None => vec![None],
        };
        let (text, origin, sets, base) = (
            problem.text.clone(),
            problem.origin.clone(),
            problem.sets.clone(),
            base.clone(),
        );
        let radii = py.detach(move || -> Result<Vec<Option<f64>>, KnobError> {
            speeds
                .iter()
                .map(|w| {
                    let speed = w.map(|w| (w, None));
                    safe_radius_search(&text, &origin, &sets, &base, speed, |_| {})
                        .map(|(_, b)| b.certified.map(|p| p.value))
                })
                .collect()
        });
        let radii = radii.map_err(knob_error)?;
        return if list {
            Ok(radii.into_pyobject(py)?.into_any().unbind())
        } else {
            Ok(radii[0].into_pyobject(py)?.into_any().unbind())
        };
    }
    let base = single(problem, "safe_radius")?;
    let list = speeds.is_some();
    let speeds = speeds.unwrap_or_else(|| vec![base.environment.obstacle_speed]);
    let radii = py.detach(move || -> Result<Vec<Option<f64>>, String> {
        speeds
            .iter()
            .map(|&w| {
                let mut p = base.clone();
                p.environment.obstacle_speed = w;
                p.validate(&format!("speeds {w}"))
                    .map_err(|e| e.to_string())?;
                radius::safe_radius(&p)
                    .map(|b| b.value)
                    .map_err(|e| e.to_string())
            })
            .collect()
    });
    let radii = radii.map_err(AnalysisError::new_err)?;
    if list {
        Ok(radii.into_pyobject(py)?.into_any().unbind())
    } else {
        Ok(radii[0].into_pyobject(py)?.into_any().unbind())
    }
}

/// The largest certified obstacle speed bound W (m/s) at the problem's reaction radius, or
/// None when none certifies.
#[pyfunction]
fn max_speed(py: Python<'_>, problem: &Problem) -> PyResult<Option<f64>> {
    if let Input::Planar(base) = &problem.input {
        let (text, origin, sets, base) = (
            problem.text.clone(),
            problem.origin.clone(),
            problem.sets.clone(),
            base.clone(),
        );
        return py
            .detach(move || max_speed_search(&text, &origin, &sets, &base, None, |_| {}))
            .map(|b| b.certified.map(|p| p.value))
            .map_err(knob_error);
    }
    let p = single(problem, "max_speed")?;
    py.detach(move || radius::max_speed(&p).map(|b| b.value))
        .map_err(|e| AnalysisError::new_err(e.to_string()))
}

/// A certified map of a box of parameters: leaves certified for every point in them, refuted
/// or undecided (`safereach region`).
#[pyclass(module = "safereach")]
struct RegionMap {
    map: LibRegionMap,
    json: Value,
}

#[pymethods]
impl RegionMap {
    /// Reads map JSON (as `region --out` writes it); it is not checked until `check`.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        let map: LibRegionMap = serde_json::from_str(text)
            .map_err(|e| InputError::new_err(format!("region map: {e}")))?;
        let json = serde_json::to_value(&map).expect("maps serialise");
        Ok(RegionMap { map, json })
    }

    /// The leaves: dicts with `box` (each ranged key to [lo, hi]), `verdict`, bound, proof.
    #[getter]
    fn leaves(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(py, &self.json["leaves"])
    }

    /// Fractions of the box certified, refuted and undecided.
    #[getter]
    fn coverage(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(py, &self.json["coverage"])
    }

    /// Re-verifies every leaf exactly, without the solver; returns whether the whole box is
    /// certified, or raises CertificateError with the reason the map is not valid.
    fn check(&self, py: Python<'_>) -> PyResult<bool> {
        let map = self.map.clone();
        py.detach(move || check_map(&map).map(|r| r.all_certified))
            .map_err(|e| CertificateError::new_err(e.to_string()))
    }

    /// The map as JSON text (as `region --out` writes it).
    fn to_json(&self) -> String {
        serde_json::to_string(&self.map).expect("maps serialise") + "\n"
    }
}

/// Maps `problem` (a problem, a scene or a planar problem) over the box `ranges` ({key:
/// (lo, hi)}, e.g. {"environment.obstacle_speed": (0.1, 0.3)}, or in a scene or a planar
/// problem {"obstacle.0.max_speed": (0.1, 0.3)}): boxes that do not certify are split down
/// to `depth` (default 14; 8 for a planar problem). The GIL is released.
#[pyfunction]
#[pyo3(signature = (problem, ranges, depth = None, min_width = 0.0))]
fn region(
    py: Python<'_>,
    problem: &Problem,
    ranges: &Bound<'_, PyDict>,
    depth: Option<u32>,
    min_width: f64,
) -> PyResult<RegionMap> {
    let depth = depth.unwrap_or(match problem.input {
        Input::Planar(_) => PLANAR_DEFAULT_DEPTH,
        _ => DEFAULT_DEPTH,
    });
    let axes = ranges
        .iter()
        .map(|(key, span)| {
            let key: String = key.extract()?;
            let (lo, hi): (f64, f64) = span.extract().map_err(|_| {
                InputError::new_err(format!("{key}: expected a pair (lo, hi) of numbers"))
            })?;
            Axis::for_key(&key, lo, hi).map_err(InputError::new_err)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let whole = ParamBox::new(axes).map_err(|e| InputError::new_err(format!("ranges: {e}")))?;
    if !(min_width.is_finite() && (0.0..1.0).contains(&min_width)) {
        return Err(InputError::new_err(format!(
            "min_width {min_width}: must be a fraction in [0, 1)"
        )));
    }
    let options = RegionOptions {
        depth,
        min_width,
        ..RegionOptions::default()
    };
    // An obstacle's own key maps a problem as the scene it is (as the CLI does).
    let input = match &problem.input {
        Input::Problem(p) if whole.axes.iter().any(|a| a.obstacle.is_some()) => {
            Input::Scene(Scene::from_problem(p))
        }
        input => input.clone(),
    };
    let (text, sets) = (problem.text.clone(), problem.sets.clone());
    let map = py
        .detach(move || match &input {
            Input::Problem(p) => {
                map_region(p, &whole, &options, &|_| {}).map_err(|e| e.to_string())
            }
            Input::Scene(s) => {
                map_scene_region(s, &whole, &options, &|_| {}).map_err(|e| e.to_string())
            }
            Input::Planar(p) => map_planar_region(&text, &sets, p, &whole, &options, &|_| {})
                .map_err(|e| e.to_string()),
        })
        .map_err(InputError::new_err)?;
    let json = serde_json::to_value(&map).expect("maps serialise");
    Ok(RegionMap { map, json })
}

/// The runtime monitor for a certified certificate: feed it samples, read its verdict
/// (`held` or `violated`, latched) and events.
#[pyclass(module = "safereach")]
struct Monitor {
    inner: LibMonitor,
}

fn event_dict(py: Python<'_>, e: &safereach::monitor::Event) -> PyResult<Py<PyAny>> {
    to_py(py, &serde_json::to_value(e).expect("events serialise"))
}

#[pymethods]
impl Monitor {
    /// A monitor for `certificate`, which must pass `check` with the verdict `certified`.
    #[new]
    fn new(certificate: &Certificate) -> PyResult<Self> {
        let inner = LibMonitor::for_certificate_file(&certificate.file)
            .map_err(|e| CertificateError::new_err(e.to_string()))?;
        Ok(Monitor { inner })
    }

    /// Checks one sample; returns (verdict, events raised by it as dicts).
    #[pyo3(signature = (t, robot_x, robot_v, obstacle_x, obstacle_v = None, obstacle_t = None, obstacle_id = 0, robot_mode = None))]
    #[allow(clippy::too_many_arguments)]
    fn observe(
        &mut self,
        py: Python<'_>,
        t: f64,
        robot_x: f64,
        robot_v: f64,
        obstacle_x: f64,
        obstacle_v: Option<f64>,
        obstacle_t: Option<f64>,
        obstacle_id: u32,
        robot_mode: Option<&str>,
    ) -> PyResult<(&'static str, Py<PyAny>)> {
        let mode = mode_of(robot_mode)?;
        let s = Sample {
            t,
            robot_x,
            robot_v,
            robot_mode: mode,
            obstacle_id,
            obstacle_x,
            obstacle_v,
            obstacle_t,
        };
        let outcome = self.inner.observe(&s);
        let events = PyList::empty(py);
        for e in outcome.events {
            events.append(event_dict(py, e)?)?;
        }
        Ok((outcome.verdict.as_str(), events.into_any().unbind()))
    }

    /// Checks a block of samples given as numpy float64 arrays of one length (obstacle_v
    /// optional: NaN-free, or None to estimate speeds; obstacle_id optional uint32 array);
    /// returns (verdict after the last, list of (index, event dict)). The GIL is released
    /// while the block is checked.
    #[pyo3(signature = (t, robot_x, robot_v, obstacle_x, obstacle_v = None, obstacle_id = None))]
    #[allow(clippy::too_many_arguments)]
    fn observe_many(
        &mut self,
        py: Python<'_>,
        t: PyReadonlyArray1<'_, f64>,
        robot_x: PyReadonlyArray1<'_, f64>,
        robot_v: PyReadonlyArray1<'_, f64>,
        obstacle_x: PyReadonlyArray1<'_, f64>,
        obstacle_v: Option<PyReadonlyArray1<'_, f64>>,
        obstacle_id: Option<PyReadonlyArray1<'_, u32>>,
    ) -> PyResult<(&'static str, Py<PyAny>)> {
        fn column<'a, T: numpy::Element>(
            a: &'a PyReadonlyArray1<'_, T>,
            name: &str,
            n: usize,
        ) -> PyResult<&'a [T]> {
            let s = a.as_slice().map_err(|_| {
                InputError::new_err(format!("{name}: the array must be contiguous"))
            })?;
            if s.len() != n {
                return Err(InputError::new_err(format!(
                    "{name}: length {} differs from t's {n}",
                    s.len()
                )));
            }
            Ok(s)
        }
        let n = t.len()?;
        let t = column(&t, "t", n)?;
        let rx = column(&robot_x, "robot_x", n)?;
        let rv = column(&robot_v, "robot_v", n)?;
        let ox = column(&obstacle_x, "obstacle_x", n)?;
        let ov = obstacle_v
            .as_ref()
            .map(|a| column(a, "obstacle_v", n))
            .transpose()?;
        let ids = obstacle_id
            .as_ref()
            .map(|a| column(a, "obstacle_id", n))
            .transpose()?;
        let inner = &mut self.inner;
        // Samples are built a block at a time into one buffer (no copy of the columns, no
        // allocation per sample), and the monitor checks each block as one call.
        let (verdict, events) = py.detach(move || {
            const BLOCK: usize = 4096;
            let mut events = Vec::new();
            let mut block: Vec<Sample> = Vec::with_capacity(BLOCK.min(n));
            let mut verdict = inner.verdict();
            for start in (0..n).step_by(BLOCK) {
                let end = (start + BLOCK).min(n);
                block.clear();
                block.extend((start..end).map(|i| Sample {
                    t: t[i],
                    robot_x: rx[i],
                    robot_v: rv[i],
                    robot_mode: None,
                    obstacle_id: ids.map_or(0, |ids| ids[i]),
                    obstacle_x: ox[i],
                    obstacle_v: ov.map(|v| v[i]),
                    obstacle_t: None,
                }));
                verdict = inner.observe_all(&block, |i, e| events.push((start + i, *e)));
            }
            (verdict, events)
        });
        let list = PyList::empty(py);
        for (i, e) in &events {
            list.append((*i, event_dict(py, e)?))?;
        }
        Ok((verdict.as_str(), list.into_any().unbind()))
    }

    /// Checks a ROS 2 bag (MCAP) as `safereach monitor run.mcap` does (docs/monitor.md §10):
    /// the robot's `nav_msgs/msg/Odometry` on `robot_topic`, obstacles on the topics the
    /// glob patterns `obstacle_topics` match (default: every Autoware `TrackedObjects`
    /// topic), the mode on `mode_topic` or inferred from speeds, positions projected on
    /// `lane_axis` (x, y, yaw) or the robot's first pose. Returns (verdict, list of (message
    /// number, event dict)), obstacles named as the bag names them. The GIL is released
    /// while the bag is read.
    #[pyo3(signature = (path, robot_topic = "/odom", obstacle_topics = None, mode_topic = None, infer_mode = false, lane_axis = None, ground_truth = false, obstacle_speed = "twist"))]
    #[allow(clippy::too_many_arguments)]
    fn observe_bag(
        &mut self,
        py: Python<'_>,
        path: std::path::PathBuf,
        robot_topic: &str,
        obstacle_topics: Option<Vec<String>>,
        mode_topic: Option<String>,
        infer_mode: bool,
        lane_axis: Option<(f64, f64, f64)>,
        ground_truth: bool,
        obstacle_speed: &str,
    ) -> PyResult<(&'static str, Py<PyAny>)> {
        let obstacle_speed = match obstacle_speed {
            "twist" => SpeedSource::Twist,
            "positions" => SpeedSource::Positions,
            other => {
                return Err(InputError::new_err(format!(
                    "obstacle_speed {other:?}: expected \"twist\" or \"positions\""
                )));
            }
        };
        if let Some((x, y, yaw)) = lane_axis
            && ![x, y, yaw].iter().all(|v| v.is_finite())
        {
            return Err(InputError::new_err(
                "lane_axis: x, y and yaw must be finite",
            ));
        }
        let options = BagOptions {
            robot_topic: robot_topic.to_string(),
            obstacle_topics: obstacle_topics.unwrap_or_default(),
            mode_topic,
            infer_mode,
            lane_axis: lane_axis.map(|(x, y, yaw)| LaneAxis::new([x, y], yaw)),
            obstacle_speed,
            ground_truth,
            ..BagOptions::default()
        };
        let file = std::fs::File::open(&path).map_err(|e| {
            InputError::new_err(format!("{}: cannot open the bag: {e}", path.display()))
        })?;
        let mut reader = BagReader::new(std::io::BufReader::with_capacity(1 << 20, file), &options)
            .map_err(|e| InputError::new_err(e.to_string()))?;
        let inner = &mut self.inner;
        let events = py.detach(move || {
            let mut events = Vec::new();
            while let Some(item) = reader.next_item() {
                let message = item.message();
                let outcome = inner.observe_bag_item(reader.ids(), &item);
                for e in outcome.events {
                    let name = e.obstacle_id.map(|id| reader.ids().name(id).to_string());
                    events.push((message, *e, name));
                }
            }
            events
        });
        let list = PyList::empty(py);
        for (message, e, name) in &events {
            let mut value = serde_json::to_value(e).expect("events serialise");
            value["obstacle_id"] = name.clone().map_or(Value::Null, Value::String);
            list.append((*message, to_py(py, &value)?))?;
        }
        Ok((self.inner.verdict().as_str(), list.into_any().unbind()))
    }

    /// The standing verdict: `held` or `violated` (latched).
    #[getter]
    fn verdict(&self) -> &'static str {
        self.inner.verdict().as_str()
    }

    /// The summary (as `monitor --json` reports it): counts, first violation, each premise's
    /// smallest margin.
    fn summary(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(
            py,
            &serde_json::to_value(self.inner.summary()).expect("summaries serialise"),
        )
    }
}

/// The runtime monitor for a planar certificate (`monitor::planar`): samples of the robot's
/// centre and one obstacle's, obstacles matched to the certificate's by name.
#[pyclass(module = "safereach")]
struct PlanarMonitor {
    inner: LibPlanarMonitor,
    /// Obstacle names seen so far, by their integer id (their index).
    names: Vec<String>,
}

#[pymethods]
impl PlanarMonitor {
    /// A monitor for the planar `certificate`, which must pass `check` as `certified`.
    #[new]
    fn new(certificate: &Certificate) -> PyResult<Self> {
        let CertificateFile::Planar(cert) = &certificate.file else {
            return Err(CertificateError::new_err(
                "not a planar certificate: use Monitor for a line's or a scene's",
            ));
        };
        let inner =
            LibPlanarMonitor::new(cert).map_err(|e| CertificateError::new_err(e.to_string()))?;
        Ok(PlanarMonitor {
            inner,
            names: Vec::new(),
        })
    }

    /// Checks one sample: the robot's centre, speed and mode, and the obstacle `obstacle`'s
    /// seen centre (and velocity, if known); None for the obstacle: a robot-only instant.
    /// Returns (verdict, events raised by it as dicts).
    #[pyo3(signature = (t, robot_x, robot_y, robot_v, obstacle = None, obstacle_x = 0.0, obstacle_y = 0.0, obstacle_vx = None, obstacle_vy = None, robot_mode = None))]
    #[allow(clippy::too_many_arguments)]
    fn observe(
        &mut self,
        py: Python<'_>,
        t: f64,
        robot_x: f64,
        robot_y: f64,
        robot_v: f64,
        obstacle: Option<&str>,
        obstacle_x: f64,
        obstacle_y: f64,
        obstacle_vx: Option<f64>,
        obstacle_vy: Option<f64>,
        robot_mode: Option<&str>,
    ) -> PyResult<(&'static str, Py<PyAny>)> {
        let robot_mode = mode_of(robot_mode)?;
        let obstacle_velocity = match (obstacle_vx, obstacle_vy) {
            (Some(x), Some(y)) => Some((x, y)),
            (None, None) => None,
            _ => {
                return Err(InputError::new_err(
                    "obstacle_vx and obstacle_vy: give both or neither",
                ));
            }
        };
        let outcome = match obstacle {
            None => self.inner.observe_robot(&PlanarRobotSample {
                t,
                robot_x,
                robot_y,
                robot_v,
                robot_mode,
            }),
            Some(name) => {
                let id = match self.names.iter().position(|n| n == name) {
                    Some(i) => i as u32,
                    None => {
                        self.names.push(name.to_string());
                        let id = self.names.len() as u32 - 1;
                        self.inner.identify(id, name);
                        id
                    }
                };
                self.inner.observe(&PlanarSample {
                    t,
                    robot_x,
                    robot_y,
                    robot_v,
                    robot_mode,
                    obstacle_id: id,
                    obstacle_x,
                    obstacle_y,
                    obstacle_velocity,
                })
            }
        };
        let events = PyList::empty(py);
        for e in outcome.events {
            events.append(event_dict(py, e)?)?;
        }
        Ok((outcome.verdict.as_str(), events.into_any().unbind()))
    }

    /// The standing verdict: `held` or `violated` (latched).
    #[getter]
    fn verdict(&self) -> &'static str {
        self.inner.verdict().as_str()
    }

    /// The summary (as `monitor --json` reports it), with its `plane` part.
    fn summary(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(
            py,
            &serde_json::to_value(self.inner.summary()).expect("summaries serialise"),
        )
    }
}

/// The mode a sample names, if any.
fn mode_of(robot_mode: Option<&str>) -> PyResult<Option<Mode>> {
    robot_mode
        .map(|m| {
            Mode::from_name(m.as_bytes()).ok_or_else(|| {
                InputError::new_err(format!(
                    "robot_mode {m:?}: expected idle, accelerate, drive, brake or stop"
                ))
            })
        })
        .transpose()
}

/// The safereach module: certify, check, radius and the runtime monitor.
#[pymodule]
fn _safereach(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<Problem>()?;
    m.add_class::<Certificate>()?;
    m.add_class::<Monitor>()?;
    m.add_class::<PlanarMonitor>()?;
    m.add_class::<RegionMap>()?;
    m.add_function(wrap_pyfunction!(region, m)?)?;
    m.add_function(wrap_pyfunction!(certify, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(safe_radius, m)?)?;
    m.add_function(wrap_pyfunction!(max_speed, m)?)?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("CertificateError", py.get_type::<CertificateError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    Ok(())
}
