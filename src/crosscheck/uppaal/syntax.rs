//! The network as data: UPPAAL's expressions and statements (the subset the export uses),
//! functions, global declarations, locations, edges and templates. The network is built once
//! as this data (`network`), then printed (`printer`) and run (`interpreter`) from the same
//! values, so what is checked is what is written.

/// A binary operator of UPPAAL's expression language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/` (the interpreter requires it to be exact)
    Div,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `==`
    Eq,
    /// `&&`
    And,
    /// `||`
    Or,
}

impl Op {
    pub(super) fn text(self) -> &'static str {
        match self {
            Op::Add => "+",
            Op::Sub => "-",
            Op::Mul => "*",
            Op::Div => "/",
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
            Op::Eq => "==",
            Op::And => "&&",
            Op::Or => "||",
        }
    }

    pub(super) fn precedence(self) -> u8 {
        match self {
            Op::Or => 1,
            Op::And => 2,
            Op::Eq => 3,
            Op::Lt | Op::Le | Op::Gt | Op::Ge => 4,
            Op::Add | Op::Sub => 5,
            Op::Mul | Op::Div => 6,
        }
    }
}

/// An expression of UPPAAL's C-like language (the subset the export uses).
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// An integer literal.
    Int(i64),
    /// `true` / `false`.
    Bool(bool),
    /// A constant, variable, parameter or local.
    Name(&'static str),
    /// `a[i]`.
    Elem(&'static str, Box<Expr>),
    /// `f(args)`.
    Call(&'static str, Vec<Expr>),
    /// `!e`.
    Not(Box<Expr>),
    /// `a op b`.
    Bin(Op, Box<Expr>, Box<Expr>),
}

/// A statement of a function body (or of an edge's update list).
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `name = e;`
    Set(&'static str, Expr),
    /// `name[i] = e;`
    SetElem(&'static str, Expr, Expr),
    /// `f(args);`
    Call(&'static str, Vec<Expr>),
    /// `if (c) { … } else { … }`
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `return e;`
    Return(Expr),
    /// `for (var = from; var > 0; var--) { … }` (`down`) or
    /// `for (var = from; var <= to; var++) { … }`.
    For {
        /// The loop variable (a local).
        var: &'static str,
        /// Its first value.
        from: Expr,
        /// Counting down to 1 (`None`) or up to this bound inclusive.
        up_to: Option<Expr>,
        /// The body.
        body: Vec<Stmt>,
    },
}

/// A function's return type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// `bool`
    Bool,
    /// `int`
    Int,
    /// `void`
    Void,
}

/// A function of the global declarations.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Comment printed above it.
    pub doc: String,
    /// Return type.
    pub ret: Ty,
    /// Name.
    pub name: &'static str,
    /// Parameters (all `int`).
    pub params: Vec<&'static str>,
    /// Local `int` variables.
    pub locals: Vec<&'static str>,
    /// Body.
    pub body: Vec<Stmt>,
}

/// A global declaration.
#[derive(Clone, Debug, PartialEq)]
pub enum Decl {
    /// A comment line (or lines).
    Comment(String),
    /// `const int NAME = v;` (or `const bool`).
    Const {
        /// Name.
        name: &'static str,
        /// Value.
        value: i64,
        /// Declared `bool`.
        boolean: bool,
        /// Trailing comment.
        note: String,
    },
    /// `const int NAME[LEN] = {…};`
    ConstArray {
        /// Name.
        name: &'static str,
        /// The length as printed (a constant's name or an expression of constants).
        len: &'static str,
        /// Values.
        values: Vec<i64>,
        /// Trailing comment.
        note: String,
    },
    /// `int[lo,hi] name = init;` or `bool name = init;` or an array of them.
    Var {
        /// Name.
        name: &'static str,
        /// Range as printed (constant names) and as numbers; `None`: `bool`.
        range: Option<(&'static str, &'static str, i64, i64)>,
        /// Array length, if an array.
        len: Option<(String, usize)>,
        /// Initial value (every element).
        init: i64,
        /// Trailing comment.
        note: String,
    },
    /// `chan a, b;`
    Chans(Vec<&'static str>),
    /// `typedef int[lo,hi] name;` (the printed bounds; a template parameter's type).
    Typedef {
        /// Name.
        name: &'static str,
        /// Lower bound as printed.
        lo: &'static str,
        /// Upper bound as printed.
        hi: &'static str,
        /// Trailing comment.
        note: String,
    },
    /// A function.
    Func(Function),
}

/// How a location delays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Time may pass (subject to its invariant).
    Normal,
    /// No delay.
    Urgent,
    /// No delay, and the next transition must leave a committed location.
    Committed,
}

/// A location of a template.
#[derive(Clone, Debug, PartialEq)]
pub struct Location {
    /// Name (UPPAAL identifier).
    pub name: &'static str,
    /// Clock invariant (printed; clocks are not interpreted).
    pub invariant: Option<&'static str>,
    /// Delay kind.
    pub kind: Kind,
    /// Position in UPPAAL's editor.
    pub xy: (i32, i32),
}

/// Direction of a synchronisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// `c!`
    Send,
    /// `c?`
    Receive,
}

/// An edge of a template.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Source location (index).
    pub source: usize,
    /// Target location (index).
    pub target: usize,
    /// `name : int[0, hi]` where hi is printed as given and interpreted as the number.
    pub select: Option<(&'static str, &'static str, i64)>,
    /// Data guard (interpreted).
    pub guard: Option<Expr>,
    /// Clock guard (printed only).
    pub clock_guard: Option<&'static str>,
    /// Synchronisation.
    pub sync: Option<(&'static str, Dir)>,
    /// Updates (interpreted).
    pub update: Vec<Stmt>,
    /// Clock resets (printed only).
    pub clock_reset: Option<&'static str>,
}

/// A template's parameter `const TYPE NAME`: the template is instantiated once for every
/// value 0..count (UPPAAL's `system` does this for a bounded integer parameter type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Param {
    /// The parameter's name (bound in the template's guards and updates).
    pub name: &'static str,
    /// Its type as printed (a `typedef` of `int[0, count - 1]`).
    pub ty: &'static str,
    /// Number of instances.
    pub count: usize,
}

/// A template: one process, or one per value of its parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    /// Name, also the process name.
    pub name: &'static str,
    /// The parameter, if the template is instantiated once per value of it.
    pub param: Option<Param>,
    /// Local declarations (clocks only).
    pub declaration: &'static str,
    /// Locations.
    pub locations: Vec<Location>,
    /// Initial location (index).
    pub init: usize,
    /// Edges.
    pub edges: Vec<Edge>,
}

/// The network: global declarations, templates and the safety query.
#[derive(Clone, Debug, PartialEq)]
pub struct Network {
    /// Header comment of the file.
    pub header: String,
    /// Global declarations.
    pub declarations: Vec<Decl>,
    /// Templates (instantiated once, or once per parameter value).
    pub templates: Vec<Template>,
    /// The comment of the `system` line.
    pub system_comment: String,
    /// The violation the safety query excludes (`A[] not violation`).
    pub violation: Expr,
    /// The comment printed with the query (in the XML and the `.q` file).
    pub query_comment: String,
}

// Shorthands for building expressions.
pub(super) fn n(name: &'static str) -> Expr {
    Expr::Name(name)
}
pub(super) fn int(v: i64) -> Expr {
    Expr::Int(v)
}
pub(super) fn call(f: &'static str) -> Expr {
    Expr::Call(f, vec![])
}
pub(super) fn elem(a: &'static str, i: Expr) -> Expr {
    Expr::Elem(a, Box::new(i))
}
pub(super) fn bin(op: Op, a: Expr, b: Expr) -> Expr {
    Expr::Bin(op, Box::new(a), Box::new(b))
}
pub(super) fn add(a: Expr, b: Expr) -> Expr {
    bin(Op::Add, a, b)
}
pub(super) fn sub(a: Expr, b: Expr) -> Expr {
    bin(Op::Sub, a, b)
}
pub(super) fn mul(a: Expr, b: Expr) -> Expr {
    bin(Op::Mul, a, b)
}
pub(super) fn div(a: Expr, b: Expr) -> Expr {
    bin(Op::Div, a, b)
}
pub(super) fn and(a: Expr, b: Expr) -> Expr {
    bin(Op::And, a, b)
}
pub(super) fn or(a: Expr, b: Expr) -> Expr {
    bin(Op::Or, a, b)
}
pub(super) fn not(a: Expr) -> Expr {
    Expr::Not(Box::new(a))
}
