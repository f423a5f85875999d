//! The network printed as UPPAAL reads it: expressions and statements as C-like text, the
//! global declarations, the XML file (templates, locations, transitions, the system and the
//! query) and the `.q` query file. Printing is a pure function of the network data.

use std::fmt::Write as _;

use super::syntax::{
    Decl, Dir, Edge, Expr, Function, Kind, Location, Network, Op, Stmt, Template, Ty,
};

/// An expression as C-like text, parenthesised where C needs it (and `&&` inside `||` for
/// the reader).
pub(super) fn show_expr(e: &Expr) -> String {
    fn go(e: &Expr, out: &mut String) {
        match e {
            Expr::Int(v) => {
                let _ = write!(out, "{v}");
            }
            Expr::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Expr::Name(x) => out.push_str(x),
            Expr::Elem(a, i) => {
                out.push_str(a);
                out.push('[');
                go(i, out);
                out.push(']');
            }
            Expr::Call(f, args) => {
                out.push_str(f);
                out.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    go(a, out);
                }
                out.push(')');
            }
            Expr::Not(a) => {
                out.push('!');
                paren(a, 7, false, out);
            }
            Expr::Bin(op, a, b) => {
                paren(a, op.precedence(), false, out);
                let _ = write!(out, " {} ", op.text());
                paren(b, op.precedence(), true, out);
            }
        }
    }
    fn paren(e: &Expr, outer: u8, right: bool, out: &mut String) {
        let inner = match e {
            Expr::Bin(op, ..) => op.precedence(),
            _ => 8,
        };
        // `&&` inside `||` is parenthesised for the reader, not for the parser.
        let clarity = outer == Op::Or.precedence() && inner == Op::And.precedence();
        if inner < outer || (right && inner == outer) || clarity {
            out.push('(');
            go(e, out);
            out.push(')');
        } else {
            go(e, out);
        }
    }
    let mut s = String::new();
    go(e, &mut s);
    s
}

fn show_stmt(s: &Stmt, indent: usize, out: &mut String) {
    let pad = "    ".repeat(indent);
    match s {
        Stmt::Set(x, e) => {
            let _ = writeln!(out, "{pad}{x} = {};", show_expr(e));
        }
        Stmt::SetElem(x, i, e) => {
            let _ = writeln!(out, "{pad}{x}[{}] = {};", show_expr(i), show_expr(e));
        }
        Stmt::Call(f, args) => {
            let _ = writeln!(out, "{pad}{};", show_expr(&Expr::Call(f, args.clone())));
        }
        Stmt::Return(e) => {
            let _ = writeln!(out, "{pad}return {};", show_expr(e));
        }
        Stmt::If(c, then, other) => {
            let _ = writeln!(out, "{pad}if ({}) {{", show_expr(c));
            for t in then {
                show_stmt(t, indent + 1, out);
            }
            if other.is_empty() {
                let _ = writeln!(out, "{pad}}}");
            } else {
                let _ = writeln!(out, "{pad}}} else {{");
                for t in other {
                    show_stmt(t, indent + 1, out);
                }
                let _ = writeln!(out, "{pad}}}");
            }
        }
        Stmt::For {
            var,
            from,
            up_to,
            body,
        } => {
            let head = match up_to {
                Some(to) => format!(
                    "for ({var} = {}; {var} <= {}; {var}++)",
                    show_expr(from),
                    show_expr(to)
                ),
                None => format!("for ({var} = {}; {var} > 0; {var}--)", show_expr(from)),
            };
            let _ = writeln!(out, "{pad}{head} {{");
            for t in body {
                show_stmt(t, indent + 1, out);
            }
            let _ = writeln!(out, "{pad}}}");
        }
    }
}

fn comment_lines(text: &str, out: &mut String) {
    for line in text.lines() {
        let _ = writeln!(out, "// {line}");
    }
}

/// The global declarations as UPPAAL text.
pub fn declarations_text(net: &Network) -> String {
    let mut out = String::new();
    for d in &net.declarations {
        declaration_text(d, &mut out);
    }
    out
}

/// One global declaration as UPPAAL text.
fn declaration_text(d: &Decl, out: &mut String) {
    match d {
        Decl::Comment(c) => {
            comment_lines(c, out);
            out.push('\n');
        }
        Decl::Const {
            name,
            value,
            boolean,
            note,
        } => {
            let value = if *boolean {
                (if *value != 0 { "true" } else { "false" }).to_string()
            } else {
                value.to_string()
            };
            let ty = if *boolean { "bool" } else { "int" };
            let _ = writeln!(out, "const {ty} {name} = {value};  // {note}");
        }
        Decl::ConstArray {
            name,
            len,
            values,
            note,
        } => {
            let list: Vec<String> = values.iter().map(i64::to_string).collect();
            let _ = writeln!(
                out,
                "const int {name}[{len}] = {{{}}};  // {note}",
                list.join(", ")
            );
        }
        Decl::Typedef { name, lo, hi, note } => {
            let _ = writeln!(out, "typedef int[{lo},{hi}] {name};  // {note}");
        }
        Decl::Var {
            name,
            range,
            len,
            init,
            note,
        } => var_text(name, *range, len, *init, note, out),
        Decl::Chans(names) => {
            let _ = writeln!(
                out,
                "chan {};  // decide: a period starts; advance: it ends",
                names.join(", ")
            );
        }
        Decl::Func(f) => function_text(f, out),
    }
}

/// A variable declaration: `int[lo,hi] name = init;` or `bool`, or an array of them.
fn var_text(
    name: &str,
    range: Option<(&str, &str, i64, i64)>,
    len: &Option<(String, usize)>,
    init: i64,
    note: &str,
    out: &mut String,
) {
    let ty = match range {
        Some((lo, hi, ..)) => format!("int[{lo},{hi}]"),
        None => "bool".to_string(),
    };
    let show_init = |v: i64| match range {
        None => (if v != 0 { "true" } else { "false" }).to_string(),
        Some(_) => v.to_string(),
    };
    match len {
        None => {
            let _ = writeln!(out, "{ty} {name} = {};  // {note}", show_init(init));
        }
        Some((text, count)) => {
            let list: Vec<String> = (0..*count).map(|_| show_init(init)).collect();
            let _ = writeln!(
                out,
                "{ty} {name}[{text}] = {{{}}};  // {note}",
                list.join(", ")
            );
        }
    }
}

/// A function of the global declarations, with its comment.
fn function_text(f: &Function, out: &mut String) {
    out.push('\n');
    if !f.doc.is_empty() {
        comment_lines(&f.doc, out);
    }
    let ret = match f.ret {
        Ty::Bool => "bool",
        Ty::Int => "int",
        Ty::Void => "void",
    };
    let params: Vec<String> = f.params.iter().map(|p| format!("int {p}")).collect();
    let _ = writeln!(out, "{ret} {}({}) {{", f.name, params.join(", "));
    for l in &f.locals {
        let _ = writeln!(out, "    int {l};");
    }
    for s in &f.body {
        show_stmt(s, 1, out);
    }
    out.push_str("}\n");
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn updates_text(e: &Edge) -> Option<String> {
    let mut parts: Vec<String> = e
        .update
        .iter()
        .map(|s| {
            let mut t = String::new();
            show_stmt(s, 0, &mut t);
            t.trim().trim_end_matches(';').to_string()
        })
        .collect();
    if let Some(r) = e.clock_reset {
        parts.push(r.to_string());
    }
    (!parts.is_empty()).then(|| parts.join(", "))
}

fn guard_text(e: &Edge) -> Option<String> {
    match (&e.clock_guard, &e.guard) {
        (None, None) => None,
        (Some(c), None) => Some(c.to_string()),
        (None, Some(g)) => Some(show_expr(g)),
        (Some(c), Some(g)) => Some(format!("{c} && ({})", show_expr(g))),
    }
}

/// The safety query (`A[] not violation`).
pub fn query_formula(net: &Network) -> String {
    format!("A[] not ({})", show_expr(&net.violation))
}

/// The seed paper's safety query, for N obstacles on lanes y at positions x (quoted in the
/// query comments).
pub(super) const SEED_QUERY: &str = "A[] forall (i:int[0,N-1]) R.y == obstacles[i].y and obstacles[i].x > R.x \
                                     and (obstacles[i].x - R.x <= 1) imply R.v == 0";

/// The model as UPPAAL XML.
pub fn xml_text(net: &Network) -> String {
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    out.push_str(
        "<!DOCTYPE nta PUBLIC '-//Uppaal Team//DTD Flat System 1.1//EN' \
         'http://www.it.uu.se/research/group/darts/uppaal/flat-1_2.dtd'>\n",
    );
    let _ = writeln!(out, "<!--\n{}\n-->", net.header.replace("--", "- -"));
    out.push_str("<nta>\n");
    let _ = writeln!(
        out,
        "  <declaration>{}</declaration>",
        xml_escape(&declarations_text(net))
    );
    for t in &net.templates {
        template_xml(net, t, &mut out);
    }
    let names: Vec<&str> = net.templates.iter().map(|t| t.name).collect();
    let _ = writeln!(
        out,
        "  <system>// {}\nsystem {};</system>",
        net.system_comment,
        names.join(", ")
    );
    out.push_str("  <queries>\n    <query>\n");
    let _ = writeln!(
        out,
        "      <formula>{}</formula>",
        xml_escape(&query_formula(net))
    );
    let _ = writeln!(
        out,
        "      <comment>{}</comment>",
        xml_escape(&net.query_comment)
    );
    out.push_str("    </query>\n  </queries>\n</nta>\n");
    out
}

/// One template as XML: its name, clock declaration, locations and transitions.
fn template_xml(net: &Network, t: &Template, out: &mut String) {
    out.push_str("  <template>\n");
    let _ = writeln!(out, "    <name>{}</name>", t.name);
    if let Some(p) = t.param {
        let _ = writeln!(out, "    <parameter>const {} {}</parameter>", p.ty, p.name);
    }
    if !t.declaration.is_empty() {
        let _ = writeln!(
            out,
            "    <declaration>{}</declaration>",
            xml_escape(t.declaration)
        );
    }
    for (i, l) in t.locations.iter().enumerate() {
        location_xml(&location_id(net, t, i), l, out);
    }
    let _ = writeln!(out, "    <init ref=\"{}\"/>", location_id(net, t, t.init));
    for e in &t.edges {
        transition_xml(net, t, e, out);
    }
    out.push_str("  </template>\n");
}

/// One location as XML.
fn location_xml(id: &str, l: &Location, out: &mut String) {
    let _ = writeln!(
        out,
        "    <location id=\"{}\" x=\"{}\" y=\"{}\">",
        id, l.xy.0, l.xy.1
    );
    let _ = writeln!(
        out,
        "      <name x=\"{}\" y=\"{}\">{}</name>",
        l.xy.0 - 20,
        l.xy.1 - 30,
        l.name
    );
    if let Some(inv) = l.invariant {
        let _ = writeln!(
            out,
            "      <label kind=\"invariant\" x=\"{}\" y=\"{}\">{}</label>",
            l.xy.0 - 20,
            l.xy.1 + 15,
            xml_escape(inv)
        );
    }
    match l.kind {
        Kind::Normal => {}
        Kind::Urgent => out.push_str("      <urgent/>\n"),
        Kind::Committed => out.push_str("      <committed/>\n"),
    }
    out.push_str("    </location>\n");
}

/// One edge of a template as an XML transition.
fn transition_xml(net: &Network, t: &Template, e: &Edge, out: &mut String) {
    out.push_str("    <transition>\n");
    let _ = writeln!(
        out,
        "      <source ref=\"{}\"/>",
        location_id(net, t, e.source)
    );
    let _ = writeln!(
        out,
        "      <target ref=\"{}\"/>",
        location_id(net, t, e.target)
    );
    if let Some((name, hi, _)) = e.select {
        let _ = writeln!(
            out,
            "      <label kind=\"select\">{name} : int[0, {}]</label>",
            xml_escape(hi)
        );
    }
    if let Some(g) = guard_text(e) {
        let _ = writeln!(
            out,
            "      <label kind=\"guard\">{}</label>",
            xml_escape(&g)
        );
    }
    if let Some((c, dir)) = e.sync {
        let mark = if dir == Dir::Send { '!' } else { '?' };
        let _ = writeln!(
            out,
            "      <label kind=\"synchronisation\">{c}{mark}</label>"
        );
    }
    if let Some(u) = updates_text(e) {
        let _ = writeln!(
            out,
            "      <label kind=\"assignment\">{}</label>",
            xml_escape(&u)
        );
    }
    out.push_str("    </transition>\n");
}

fn location_id(net: &Network, t: &Template, i: usize) -> String {
    let before: usize = net
        .templates
        .iter()
        .take_while(|o| o.name != t.name)
        .map(|o| o.locations.len())
        .sum();
    format!("id{}", before + i)
}

/// The query file (UPPAAL's `.q` format: comments and one formula).
pub fn query_text(net: &Network) -> String {
    format!("/*\n{}\n*/\n{}\n", net.query_comment, query_formula(net))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crosscheck::uppaal::syntax::{add, and, bin, div, int, mul, n, not, or, sub};

    #[test]
    fn expressions_print_with_the_parentheses_c_needs() {
        let e = sub(n("a"), sub(n("b"), n("c")));
        assert_eq!(show_expr(&e), "a - (b - c)");
        let e = mul(add(n("a"), n("b")), n("c"));
        assert_eq!(show_expr(&e), "(a + b) * c");
        let e = div(mul(n("a"), n("b")), mul(int(2), n("c")));
        assert_eq!(show_expr(&e), "a * b / (2 * c)");
        let e = not(or(n("a"), and(n("b"), n("c"))));
        assert_eq!(show_expr(&e), "!(a || (b && c))");
        let e = bin(Op::Le, sub(n("o"), n("B")), add(n("x"), n("y")));
        assert_eq!(show_expr(&e), "o - B <= x + y");
    }
}
