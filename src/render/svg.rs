//! A small SVG writer in table coordinates: metres in, pixels out, y pointing up on the page.

use std::fmt::Write as _;

use nalgebra::Point2;

/// How a shape is painted.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// Fill colour (any SVG colour), or `none`.
    pub fill: String,
    /// Stroke colour, or `none`.
    pub stroke: String,
    /// Stroke width in pixels.
    pub stroke_width: f64,
    /// Fill opacity in `[0, 1]`.
    pub fill_opacity: f64,
    /// Dash pattern in pixels (`"4 3"`), empty for a solid line.
    pub dash: String,
}

impl Style {
    /// A filled shape with a thin outline.
    pub fn filled(fill: &str, stroke: &str) -> Self {
        Self {
            fill: fill.to_string(),
            stroke: stroke.to_string(),
            stroke_width: 1.0,
            fill_opacity: 1.0,
            dash: String::new(),
        }
    }

    /// An unfilled outline.
    pub fn outline(stroke: &str, stroke_width: f64) -> Self {
        Self {
            fill: "none".to_string(),
            stroke: stroke.to_string(),
            stroke_width,
            fill_opacity: 1.0,
            dash: String::new(),
        }
    }

    fn attributes(&self) -> String {
        let mut out = format!(
            "fill=\"{}\" stroke=\"{}\" stroke-width=\"{}\"",
            escape(&self.fill),
            escape(&self.stroke),
            round(self.stroke_width)
        );
        if self.fill_opacity < 1.0 {
            let _ = write!(out, " fill-opacity=\"{}\"", round(self.fill_opacity));
        }
        if !self.dash.is_empty() {
            let _ = write!(out, " stroke-dasharray=\"{}\"", escape(&self.dash));
        }
        out
    }
}

/// A page that maps the table rectangle `[min, max]` to pixels.
#[derive(Clone, Debug)]
pub struct Canvas {
    min: Point2<f64>,
    max: Point2<f64>,
    scale: f64,
    margin: f64,
    extra_bottom: f64,
    body: String,
}

impl Canvas {
    /// A page for the table rectangle `[min, max]` (metres) at `scale` pixels per metre, with
    /// `margin` pixels around it and `extra_bottom` more pixels below (for a scale bar or legend).
    pub fn new(
        min: Point2<f64>,
        max: Point2<f64>,
        scale: f64,
        margin: f64,
        extra_bottom: f64,
    ) -> Self {
        Self {
            min,
            max,
            scale,
            margin,
            extra_bottom,
            body: String::new(),
        }
    }

    /// Page width in pixels.
    pub fn width(&self) -> f64 {
        (self.max.x - self.min.x) * self.scale + 2.0 * self.margin
    }

    /// Page height in pixels.
    pub fn height(&self) -> f64 {
        (self.max.y - self.min.y) * self.scale + 2.0 * self.margin + self.extra_bottom
    }

    /// Pixels per metre.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The pixel position of a table point.
    pub fn to_page(&self, p: &Point2<f64>) -> (f64, f64) {
        (
            self.margin + (p.x - self.min.x) * self.scale,
            self.margin + (self.max.y - p.y) * self.scale,
        )
    }

    /// A closed polygon through table points.
    pub fn polygon(&mut self, points: &[Point2<f64>], style: &Style) {
        let list: Vec<String> = points
            .iter()
            .map(|p| {
                let (x, y) = self.to_page(p);
                format!("{},{}", round(x), round(y))
            })
            .collect();
        let _ = writeln!(
            self.body,
            "<polygon points=\"{}\" {}/>",
            list.join(" "),
            style.attributes()
        );
    }

    /// A straight segment between table points.
    pub fn line(&mut self, from: &Point2<f64>, to: &Point2<f64>, style: &Style) {
        let (x1, y1) = self.to_page(from);
        let (x2, y2) = self.to_page(to);
        let _ = writeln!(
            self.body,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            round(x1),
            round(y1),
            round(x2),
            round(y2),
            style.attributes()
        );
    }

    /// A segment with an arrow head at `to`, the head `head` pixels long.
    pub fn arrow(&mut self, from: &Point2<f64>, to: &Point2<f64>, head: f64, style: &Style) {
        self.line(from, to, style);
        let (x1, y1) = self.to_page(from);
        let (x2, y2) = self.to_page(to);
        let (dx, dy) = (x2 - x1, y2 - y1);
        let length = dx.hypot(dy);
        if length == 0.0 {
            return;
        }
        let (ux, uy) = (dx / length, dy / length);
        let (bx, by) = (x2 - ux * head, y2 - uy * head);
        let (px, py) = (-uy * head * 0.45, ux * head * 0.45);
        let mut head_style = style.clone();
        head_style.fill = style.stroke.clone();
        head_style.fill_opacity = 1.0;
        let _ = writeln!(
            self.body,
            "<polygon points=\"{},{} {},{} {},{}\" {}/>",
            round(x2),
            round(y2),
            round(bx + px),
            round(by + py),
            round(bx - px),
            round(by - py),
            head_style.attributes()
        );
    }

    /// A circle of `radius` pixels at a table point.
    pub fn dot(&mut self, at: &Point2<f64>, radius: f64, style: &Style) {
        let (x, y) = self.to_page(at);
        let _ = writeln!(
            self.body,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {}/>",
            round(x),
            round(y),
            round(radius),
            style.attributes()
        );
    }

    /// Text centred on a table point, `size` pixels high.
    pub fn label(&mut self, at: &Point2<f64>, text: &str, size: f64, colour: &str) {
        let (x, y) = self.to_page(at);
        self.page_text(x, y, text, size, colour, "middle");
    }

    /// Text at a pixel position (for scale bars and legends), anchored `start`, `middle` or `end`.
    pub fn page_text(&mut self, x: f64, y: f64, text: &str, size: f64, colour: &str, anchor: &str) {
        let _ = writeln!(
            self.body,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" fill=\"{}\" text-anchor=\"{}\" \
             dominant-baseline=\"central\">{}</text>",
            round(x),
            round(y),
            round(size),
            escape(colour),
            escape(anchor),
            escape(text)
        );
    }

    /// A straight segment between pixel positions.
    pub fn page_line(&mut self, from: (f64, f64), to: (f64, f64), style: &Style) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            round(from.0),
            round(from.1),
            round(to.0),
            round(to.1),
            style.attributes()
        );
    }

    /// Opens a group with a class name (a layer), closed by [`Canvas::end_group`].
    pub fn begin_group(&mut self, class: &str) {
        let _ = writeln!(self.body, "<g class=\"{}\">", escape(class));
    }

    /// Closes the group opened last.
    pub fn end_group(&mut self) {
        self.body.push_str("</g>\n");
    }

    /// The finished SVG document.
    pub fn finish(&self, title: &str) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
             font-family=\"sans-serif\">\n<title>{}</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{}</svg>\n",
            escape(title),
            self.body,
            w = round(self.width()),
            h = round(self.height()),
        )
    }
}

/// Two decimals are far below a pixel and keep files small and stable.
fn round(value: f64) -> String {
    let rounded = (value * 100.0).round() / 100.0;
    if rounded == 0.0 {
        "0".to_string()
    } else {
        format!("{rounded}")
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
