//! A tiny SVG writer shared by both figures: the document frame, text (always escaped),
//! titles and rotated axis labels, rectangles, paths and circles, one element per line.
//!
//! Coordinates are taken as anything printable so each figure keeps its own number format
//! (whole pixels in the heat map; `{:.1}` via [`d1`] or plain `f64` in the curve plot).

use std::fmt::{Display, Write as _};

const FONT: &str = "font-family=\"DejaVu Sans, Verdana, sans-serif\"";

/// Text anchored at its middle.
pub(super) const MIDDLE: &str = " text-anchor=\"middle\"";
/// Text anchored at its end (right-aligned).
pub(super) const END: &str = " text-anchor=\"end\"";

/// `v` with one decimal, as coordinates computed in `f64` are printed.
pub(super) fn d1(v: f64) -> String {
    format!("{v:.1}")
}

/// `s` safe inside an SVG text element: `&` and `<` escaped. `>` needs no escape in XML
/// character data and is kept as written, as in the speed labels' `(> V_a)`.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;")
}

/// An SVG document being written.
pub(super) struct Svg {
    out: String,
}

impl Svg {
    /// A `width` × `height` document on a white background.
    pub(super) fn new(width: u32, height: u32) -> Svg {
        let (w, h) = (width, height);
        Svg {
            out: format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" {FONT} font-size=\"12\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"
            ),
        }
    }

    /// A text element; `attrs` (each with a leading space) follow the position.
    pub(super) fn text(&mut self, x: impl Display, y: impl Display, attrs: &str, body: &str) {
        let body = esc(body);
        let _ = writeln!(self.out, "<text x=\"{x}\" y=\"{y}\"{attrs}>{body}</text>");
    }

    /// The figure's title, centred on `x` at the top.
    pub(super) fn title(&mut self, x: impl Display, title: &str) {
        self.text(x, 24, &format!(" font-size=\"15\"{MIDDLE}"), title);
    }

    /// The vertical axis label, read bottom to top, centred on `y` at the left edge.
    pub(super) fn vertical_label(&mut self, y: impl Display, label: &str) {
        let rotate = format!("{MIDDLE} transform=\"rotate(-90 18 {y})\"");
        self.text(18, y, &rotate, label);
    }

    /// A filled rectangle; `attrs` (each with a leading space) follow the fill.
    pub(super) fn rect(
        &mut self,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        fill: &str,
        attrs: &str,
    ) {
        let _ = writeln!(
            self.out,
            "<rect x=\"{x}\" y=\"{y}\" width=\"{width}\" height=\"{height}\" fill=\"{fill}\"{attrs}/>"
        );
    }

    /// A filled rectangle at fractional coordinates (one decimal); `attrs` as for
    /// [`Svg::rect`].
    pub(super) fn area(
        &mut self,
        x: f64,
        y: f64,
        width: f64,
        height: f64,
        fill: &str,
        attrs: &str,
    ) {
        let _ = writeln!(
            self.out,
            "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{width:.1}\" height=\"{height:.1}\" fill=\"{fill}\"{attrs}/>"
        );
    }

    /// A path with data `d`; `attrs` (each with a leading space) give its stroke and fill.
    pub(super) fn path(&mut self, d: &str, attrs: &str) {
        let _ = writeln!(self.out, "<path d=\"{d}\"{attrs}/>");
    }

    /// A filled circle of radius `r`; `attrs` (each with a leading space) follow the fill.
    pub(super) fn circle(
        &mut self,
        cx: impl Display,
        cy: impl Display,
        r: u32,
        fill: &str,
        attrs: &str,
    ) {
        let _ = writeln!(
            self.out,
            "<circle cx=\"{cx}\" cy=\"{cy}\" r=\"{r}\" fill=\"{fill}\"{attrs}/>"
        );
    }

    /// A circle of radius `r` at fractional coordinates (one decimal); `attrs` as for
    /// [`Svg::circle`].
    pub(super) fn disc(&mut self, cx: f64, cy: f64, r: f64, fill: &str, attrs: &str) {
        let _ = writeln!(
            self.out,
            "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{r:.1}\" fill=\"{fill}\"{attrs}/>"
        );
    }

    /// The finished document.
    pub(super) fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }
}
