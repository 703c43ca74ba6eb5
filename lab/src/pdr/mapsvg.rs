//! An SVG of tracks on a floor plan: the plan's image under them when there is one
//! (`floor_image.png`, covering exactly the plan's width × height, embedded so the
//! file stands alone), else the plan's walls; plan metres x east, y north.

use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::map::{FloorPlan, GeoReference};

/// Pixels per metre of the plan (clamped so the whole plan stays 400–1600 px wide).
const PX_PER_M: f64 = 4.0;
const MIN_WIDTH_PX: f64 = 400.0;
const MAX_WIDTH_PX: f64 = 1600.0;
/// The view shows the tracks with this much plan around them, m.
const VIEW_MARGIN_M: f64 = 15.0;
/// Width of the view, px.
const VIEW_WIDTH_PX: f64 = 900.0;

/// One thing to draw: a line through the points, or the points as dots.
pub struct Layer<'a> {
    pub name: &'a str,
    pub color: &'a str,
    pub points: &'a [(f64, f64)],
    pub dots: bool,
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Draw `layers` on `plan` into `path` (the image `image` under them when given).
pub fn map_svg(
    path: &Path,
    title: &str,
    plan: &FloorPlan,
    image: Option<&Path>,
    layers: &[Layer],
) -> Result<(), String> {
    let frame = Frame::new(plan, layers);
    let mut svg = frame.header(title);
    frame.background(&mut svg, plan, image);
    for (i, l) in layers.iter().enumerate() {
        frame.layer(&mut svg, i, l);
    }
    svg.push_str("</svg>\n");
    std::fs::write(path, svg).map_err(|e| format!("{}: {e}", path.display()))
}

/// Where the drawing is: the plan's box in metres, its scale, and the view (px).
struct Frame {
    /// The plan's box, m: x min, y min, x max, y max.
    b: [f64; 4],
    /// px per m.
    s: f64,
    /// The whole drawing, px.
    w: f64,
    h: f64,
    /// The view, px: x min, y min, x max, y max, and its width and height.
    v: [f64; 4],
    vw: f64,
    vh: f64,
}

/// The points of `points` with finite coordinates.
fn finite(points: &[(f64, f64)]) -> impl Iterator<Item = &(f64, f64)> {
    points.iter().filter(|p| p.0.is_finite() && p.1.is_finite())
}

impl Frame {
    /// The drawing covers the plan's image frame (competition plans: 0..width,
    /// 0..height), else the walkable outlines' box; the view shows the tracks and some
    /// plan around them.
    fn new(plan: &FloorPlan, layers: &[Layer]) -> Self {
        let b = match plan.geo_reference() {
            Some(GeoReference::BoundingBox {
                width_m, height_m, ..
            }) => [0.0, 0.0, *width_m, *height_m],
            _ => plan.bounds(),
        };
        let (w_m, h_m) = ((b[2] - b[0]).max(1.0), (b[3] - b[1]).max(1.0));
        let s = (PX_PER_M * w_m).clamp(MIN_WIDTH_PX, MAX_WIDTH_PX) / w_m;
        let mut f = Frame {
            b,
            s,
            w: w_m * s,
            h: h_m * s,
            v: [0.0; 4],
            vw: 0.0,
            vh: 0.0,
        };
        f.v = f.view(layers);
        (f.vw, f.vh) = ((f.v[2] - f.v[0]).max(1.0), (f.v[3] - f.v[1]).max(1.0));
        f
    }

    /// Plan metres to drawing pixels (y down).
    fn px(&self, x: f64, y: f64) -> (f64, f64) {
        ((x - self.b[0]) * self.s, (self.b[3] - y) * self.s)
    }

    /// The box of the layers' points and [`VIEW_MARGIN_M`] around it, within the
    /// drawing (the whole drawing without a point).
    fn view(&self, layers: &[Layer]) -> [f64; 4] {
        let mut v = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for p in layers.iter().flat_map(|l| finite(l.points)) {
            let (x, y) = self.px(p.0, p.1);
            v = [v[0].min(x), v[1].min(y), v[2].max(x), v[3].max(y)];
        }
        let m = VIEW_MARGIN_M * self.s;
        if v[0].is_finite() {
            [
                (v[0] - m).max(0.0),
                (v[1] - m).max(0.0),
                (v[2] + m).min(self.w),
                (v[3] + m).min(self.h),
            ]
        } else {
            [0.0, 0.0, self.w, self.h]
        }
    }

    /// Line width, px of the view.
    fn stroke(&self) -> f64 {
        2.0 * self.vw / VIEW_WIDTH_PX
    }

    /// The `<svg>` element, the title and the white background.
    fn header(&self, title: &str) -> String {
        let (v, vw, vh) = (self.v, self.vw, self.vh);
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{VIEW_WIDTH_PX:.0}\" height=\"{:.0}\" viewBox=\"{:.1} {:.1} {vw:.1} {:.1}\">\n<title>{}</title>\n<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{vw:.1}\" height=\"{:.1}\" fill=\"white\"/>\n",
            (vh + 24.0 * vw / VIEW_WIDTH_PX) * VIEW_WIDTH_PX / vw,
            v[0],
            v[1],
            vh + 24.0 * vw / VIEW_WIDTH_PX,
            xml(title),
            v[0],
            v[1],
            vh + 24.0 * vw / VIEW_WIDTH_PX,
        )
    }

    /// The plan's image when it can be read, else its walls.
    fn background(&self, svg: &mut String, plan: &FloorPlan, image: Option<&Path>) {
        let (w, h) = (self.w, self.h);
        match image.and_then(|p| std::fs::read(p).ok()) {
            Some(png) => {
                let _ = writeln!(
                    svg,
                    "<image x=\"0\" y=\"0\" width=\"{w:.1}\" height=\"{h:.1}\" preserveAspectRatio=\"none\" opacity=\"0.6\" href=\"data:image/png;base64,{}\"/>",
                    base64(&png)
                );
            }
            None => {
                let mut d = String::new();
                for wall in plan.walls() {
                    let (a, c) = (self.px(wall[0], wall[1]), self.px(wall[2], wall[3]));
                    let _ = write!(d, "M{:.1} {:.1}L{:.1} {:.1}", a.0, a.1, c.0, c.1);
                }
                let _ = writeln!(
                    svg,
                    "<path d=\"{d}\" stroke=\"#888\" stroke-width=\"{:.2}\" fill=\"none\"/>",
                    0.5 * self.stroke()
                );
            }
        }
    }

    /// Layer `i`: its dots or its line, and its legend entry.
    fn layer(&self, svg: &mut String, i: usize, l: &Layer) {
        let (vw, stroke) = (self.vw, self.stroke());
        if l.dots {
            for p in finite(l.points) {
                let (x, y) = self.px(p.0, p.1);
                let _ = writeln!(
                    svg,
                    "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{:.2}\" fill=\"{}\"/>",
                    1.5 * stroke,
                    l.color
                );
            }
        } else {
            let mut d = String::new();
            for p in finite(l.points) {
                let (x, y) = self.px(p.0, p.1);
                let _ = write!(d, "{}{x:.1} {y:.1}", if d.is_empty() { "M" } else { "L" });
            }
            let _ = writeln!(
                svg,
                "<path d=\"{d}\" stroke=\"{}\" stroke-width=\"{stroke:.2}\" fill=\"none\" stroke-linejoin=\"round\"/>",
                l.color
            );
        }
        let legend_y = self.v[3] + 17.0 * vw / VIEW_WIDTH_PX;
        let font = 13.0 * vw / VIEW_WIDTH_PX;
        let _ = writeln!(
            svg,
            "<text x=\"{:.1}\" y=\"{legend_y:.1}\" font-family=\"sans-serif\" font-size=\"{font:.1}\" fill=\"{}\">{}</text>",
            self.v[0] + (8.0 + 190.0 * i as f64) * vw / VIEW_WIDTH_PX,
            l.color,
            xml(l.name)
        );
    }
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_of_known_strings() {
        assert_eq!(super::base64(b""), "");
        assert_eq!(super::base64(b"f"), "Zg==");
        assert_eq!(super::base64(b"fo"), "Zm8=");
        assert_eq!(super::base64(b"foobar"), "Zm9vYmFy");
    }
}
