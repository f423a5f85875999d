//! Evaluation of the network's data as UPPAAL evaluates it: the constants, the layout of
//! the variables in one flat vector, function calls with their parameters and locals, and
//! every expression and statement — checking on every step what UPPAAL would abort on (an
//! `int` beyond 32 bits, an assignment outside a variable's declared range, an index out of
//! bounds) and that every division is exact (the grid promises it).

use rustc_hash::FxHashMap;

use super::printer::show_expr;
use super::syntax::{Decl, Edge, Expr, Function, Network, Op, Stmt, Ty};
use super::{INT_MAX, UppaalError};

/// Storage of one global variable in the flat state vector.
#[derive(Clone, Debug)]
struct Slot {
    offset: usize,
    len: Option<usize>,
    lo: i64,
    hi: i64,
}

/// Constants, variable layout and functions of a network, for evaluation.
pub(super) struct Machine<'a> {
    consts: FxHashMap<&'static str, i64>,
    const_arrays: FxHashMap<&'static str, &'a [i64]>,
    slots: FxHashMap<&'static str, Slot>,
    funcs: FxHashMap<&'static str, &'a Function>,
    init: Vec<i64>,
}

/// The parameters and locals of a call (or an edge's `select` choice), innermost last.
pub(super) type Frame = Vec<(&'static str, i64)>;

/// How a statement ends: on to the next one, or returning a value.
enum Flow {
    Next,
    Return(i64),
}

/// A run-time failure of the network.
fn fail<T>(msg: String) -> Result<T, UppaalError> {
    Err(UppaalError::Run(msg))
}

/// `v`, if it fits UPPAAL's 32-bit `int` (`what` names it otherwise).
fn int32(v: i64, what: &dyn Fn() -> String) -> Result<i64, UppaalError> {
    if v.abs() > INT_MAX {
        return fail(format!("{} overflows a 32-bit int ({v})", what()));
    }
    Ok(v)
}

impl<'a> Machine<'a> {
    /// The machine of a network: its constants, functions and variable layout.
    pub(super) fn new(net: &'a Network) -> Machine<'a> {
        let mut m = Machine {
            consts: FxHashMap::default(),
            const_arrays: FxHashMap::default(),
            slots: FxHashMap::default(),
            funcs: FxHashMap::default(),
            init: Vec::new(),
        };
        for d in &net.declarations {
            match d {
                Decl::Const { name, value, .. } => {
                    m.consts.insert(name, *value);
                }
                Decl::ConstArray { name, values, .. } => {
                    m.const_arrays.insert(name, values);
                }
                Decl::Var {
                    name,
                    range,
                    len,
                    init,
                    ..
                } => {
                    let (lo, hi) = range.map_or((0, 1), |(_, _, lo, hi)| (lo, hi));
                    let count = len.as_ref().map(|(_, c)| *c);
                    m.slots.insert(
                        name,
                        Slot {
                            offset: m.init.len(),
                            len: count,
                            lo,
                            hi,
                        },
                    );
                    m.init
                        .extend(std::iter::repeat_n(*init, count.unwrap_or(1)));
                }
                Decl::Func(f) => {
                    m.funcs.insert(f.name, f);
                }
                Decl::Comment(_) | Decl::Chans(_) | Decl::Typedef { .. } => {}
            }
        }
        m
    }

    /// The initial value of every variable, in layout order.
    pub(super) fn initial_vars(&self) -> &[i64] {
        &self.init
    }

    /// Where the scalar variable `name` is stored in the variable vector.
    pub(super) fn offset(&self, name: &str) -> usize {
        self.slots[name].offset
    }

    fn lookup(&self, name: &str, frame: &Frame, vars: &[i64]) -> Result<i64, UppaalError> {
        if let Some((_, v)) = frame.iter().rev().find(|(x, _)| *x == name) {
            return Ok(*v);
        }
        if let Some(s) = self.slots.get(name) {
            if s.len.is_some() {
                return fail(format!("array {name} used as a scalar"));
            }
            return Ok(vars[s.offset]);
        }
        match self.consts.get(name) {
            Some(v) => Ok(*v),
            None => fail(format!("unknown name {name}")),
        }
    }

    fn element(&self, name: &str, i: i64, vars: &[i64]) -> Result<i64, UppaalError> {
        if let Some(values) = self.const_arrays.get(name) {
            return usize::try_from(i)
                .ok()
                .and_then(|i| values.get(i).copied())
                .map_or_else(|| fail(format!("{name}[{i}] out of bounds")), Ok);
        }
        let s = self
            .slots
            .get(name)
            .ok_or_else(|| UppaalError::Run(format!("unknown array {name}")))?;
        let len = s.len.unwrap_or(0) as i64;
        if i < 0 || i >= len {
            return fail(format!("{name}[{i}] out of bounds (length {len})"));
        }
        Ok(vars[s.offset + i as usize])
    }

    /// The value of `e` (`bool`s as 0 and 1) in the call frame `frame`; function calls may
    /// assign to `vars`.
    pub(super) fn eval(
        &self,
        e: &Expr,
        frame: &Frame,
        vars: &mut [i64],
    ) -> Result<i64, UppaalError> {
        Ok(match e {
            Expr::Int(v) => *v,
            Expr::Bool(b) => i64::from(*b),
            Expr::Name(x) => self.lookup(x, frame, vars)?,
            Expr::Elem(a, i) => {
                let i = self.eval(i, frame, vars)?;
                self.element(a, i, vars)?
            }
            Expr::Call(f, args) => {
                let mut values = Vec::with_capacity(args.len());
                for a in args {
                    values.push(self.eval(a, frame, vars)?);
                }
                self.call(f, &values, vars)?
            }
            Expr::Not(a) => i64::from(self.eval(a, frame, vars)? == 0),
            Expr::Bin(Op::And, a, b) => {
                i64::from(self.eval(a, frame, vars)? != 0 && self.eval(b, frame, vars)? != 0)
            }
            Expr::Bin(Op::Or, a, b) => {
                i64::from(self.eval(a, frame, vars)? != 0 || self.eval(b, frame, vars)? != 0)
            }
            Expr::Bin(op, a, b) => {
                let x = self.eval(a, frame, vars)?;
                let y = self.eval(b, frame, vars)?;
                let what = || show_expr(e);
                match op {
                    Op::Add => int32(x + y, &what)?,
                    Op::Sub => int32(x - y, &what)?,
                    Op::Mul => int32(x * y, &what)?,
                    Op::Div => {
                        if y == 0 {
                            return fail(format!("{} divides by zero", what()));
                        }
                        if x % y != 0 {
                            return fail(format!(
                                "{} = {x}/{y} is not exact: the grid would round",
                                what()
                            ));
                        }
                        x / y
                    }
                    Op::Lt => i64::from(x < y),
                    Op::Le => i64::from(x <= y),
                    Op::Gt => i64::from(x > y),
                    Op::Ge => i64::from(x >= y),
                    Op::Eq => i64::from(x == y),
                    Op::And | Op::Or => unreachable!("handled above"),
                }
            }
        })
    }

    fn call(&self, f: &str, args: &[i64], vars: &mut [i64]) -> Result<i64, UppaalError> {
        let func = self
            .funcs
            .get(f)
            .ok_or_else(|| UppaalError::Run(format!("unknown function {f}")))?;
        if func.params.len() != args.len() {
            return fail(format!("{f} called with {} arguments", args.len()));
        }
        let mut frame: Frame = func
            .params
            .iter()
            .copied()
            .zip(args.iter().copied())
            .collect();
        frame.extend(func.locals.iter().map(|l| (*l, 0)));
        match self.exec_all(&func.body, &mut frame, vars)? {
            Flow::Return(v) => Ok(v),
            Flow::Next if func.ret == Ty::Void => Ok(0),
            Flow::Next => fail(format!("{f} ends without returning a value")),
        }
    }

    fn assign(
        &self,
        name: &str,
        index: Option<i64>,
        value: i64,
        frame: &mut Frame,
        vars: &mut [i64],
    ) -> Result<(), UppaalError> {
        if index.is_none()
            && let Some(slot) = frame.iter_mut().rev().find(|(x, _)| *x == name)
        {
            slot.1 = int32(value, &|| name.to_string())?;
            return Ok(());
        }
        let s = self
            .slots
            .get(name)
            .ok_or_else(|| UppaalError::Run(format!("assignment to {name}, not a variable")))?;
        let at = match (index, s.len) {
            (None, None) => s.offset,
            (Some(i), Some(len)) if i >= 0 && (i as usize) < len => s.offset + i as usize,
            _ => return fail(format!("bad assignment to {name}[{index:?}]")),
        };
        if value < s.lo || value > s.hi {
            return fail(format!(
                "{name} = {value} is outside its declared range [{}, {}] (UPPAAL aborts)",
                s.lo, s.hi
            ));
        }
        vars[at] = value;
        Ok(())
    }

    fn exec_all(
        &self,
        body: &[Stmt],
        frame: &mut Frame,
        vars: &mut [i64],
    ) -> Result<Flow, UppaalError> {
        for s in body {
            if let Flow::Return(v) = self.exec(s, frame, vars)? {
                return Ok(Flow::Return(v));
            }
        }
        Ok(Flow::Next)
    }

    fn exec(&self, s: &Stmt, frame: &mut Frame, vars: &mut [i64]) -> Result<Flow, UppaalError> {
        match s {
            Stmt::Set(x, e) => {
                let v = self.eval(e, frame, vars)?;
                self.assign(x, None, v, frame, vars)?;
            }
            Stmt::SetElem(x, i, e) => {
                let i = self.eval(i, frame, vars)?;
                let v = self.eval(e, frame, vars)?;
                self.assign(x, Some(i), v, frame, vars)?;
            }
            Stmt::Call(f, args) => {
                self.eval(&Expr::Call(f, args.clone()), frame, vars)?;
            }
            Stmt::If(c, then, other) => {
                let branch = if self.eval(c, frame, vars)? != 0 {
                    then
                } else {
                    other
                };
                return self.exec_all(branch, frame, vars);
            }
            Stmt::Return(e) => return Ok(Flow::Return(self.eval(e, frame, vars)?)),
            Stmt::For {
                var,
                from,
                up_to,
                body,
            } => {
                let start = self.eval(from, frame, vars)?;
                self.assign(var, None, start, frame, vars)?;
                loop {
                    let j = self.lookup(var, frame, vars)?;
                    let go_on = match up_to {
                        Some(to) => j <= self.eval(to, frame, vars)?,
                        None => j > 0,
                    };
                    if !go_on {
                        break;
                    }
                    if let Flow::Return(v) = self.exec_all(body, frame, vars)? {
                        return Ok(Flow::Return(v));
                    }
                    let step = if up_to.is_some() { 1 } else { -1 };
                    self.assign(var, None, j + step, frame, vars)?;
                }
            }
        }
        Ok(Flow::Next)
    }

    /// Whether an edge's guard holds (no guard: true).
    pub(super) fn truth(
        &self,
        e: &Option<Expr>,
        frame: &Frame,
        vars: &mut [i64],
    ) -> Result<bool, UppaalError> {
        match e {
            None => Ok(true),
            Some(e) => Ok(self.eval(e, frame, vars)? != 0),
        }
    }

    /// Runs an edge's updates in order.
    pub(super) fn update(
        &self,
        e: &Edge,
        frame: &mut Frame,
        vars: &mut [i64],
    ) -> Result<(), UppaalError> {
        for s in &e.update {
            self.exec(s, frame, vars)?;
        }
        Ok(())
    }
}
