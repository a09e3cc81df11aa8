//! A minimal log-log line plot written as SVG text, for the plots BENCHMARKS.md shows.

/// One named line of (x, y) points, x and y > 0.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Drawn black and dashed over the others: a Pareto front.
    pub front: bool,
}

impl Series {
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.into(),
            points,
            front: false,
        }
    }

    /// The Pareto front through `points`.
    pub fn front(points: Vec<(f64, f64)>) -> Self {
        Series {
            name: "Pareto front".into(),
            points,
            front: true,
        }
    }
}

const WIDTH: f64 = 780.0;
const HEIGHT: f64 = 400.0;
const MARGIN: f64 = 60.0;
/// The plot area's right edge; the legend sits right of it, clear of the lines.
const RIGHT: f64 = WIDTH - 170.0;
const COLORS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2",
];

/// A log-log plot of `series` with axis labels and a decade grid.
pub fn log_log(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> String {
    let all = series.iter().flat_map(|s| s.points.iter());
    let (x0, x1, y0, y1) = all.fold(
        (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
        |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
    );
    let (lx0, lx1) = (x0.log10().floor(), x1.log10().ceil());
    let (ly0, ly1) = (y0.log10().floor(), y1.log10().ceil());
    let sx = |x: f64| MARGIN + (x.log10() - lx0) / (lx1 - lx0).max(1.0) * (RIGHT - MARGIN);
    let sy = |y: f64| {
        HEIGHT - MARGIN - (y.log10() - ly0) / (ly1 - ly0).max(1.0) * (HEIGHT - 2.0 * MARGIN)
    };
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">{title}</text>\n\
         <text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{x_label}</text>\n\
         <text x=\"16\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 16 {})\">{y_label}</text>\n",
        WIDTH / 2.0,
        (MARGIN + RIGHT) / 2.0,
        HEIGHT - 16.0,
        HEIGHT / 2.0,
        HEIGHT / 2.0
    );
    for decade in lx0 as i32..=lx1 as i32 {
        let x = sx(10f64.powi(decade));
        svg += &format!(
            "<line x1=\"{x}\" y1=\"{MARGIN}\" x2=\"{x}\" y2=\"{}\" stroke=\"#ddd\"/>\n\
             <text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">1e{decade}</text>\n",
            HEIGHT - MARGIN,
            HEIGHT - MARGIN + 16.0
        );
    }
    for decade in ly0 as i32..=ly1 as i32 {
        let y = sy(10f64.powi(decade));
        svg += &format!(
            "<line x1=\"{MARGIN}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#ddd\"/>\n\
             <text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{decade}</text>\n",
            RIGHT,
            MARGIN - 6.0,
            y + 4.0
        );
    }
    // Fronts last, so that they are drawn over the lines they pick points from.
    let (lines, fronts): (Vec<_>, Vec<_>) = series.iter().partition(|s| !s.front);
    for (k, s) in lines.iter().chain(&fronts).enumerate() {
        let (color, dash) = match s.front {
            true => ("black", " stroke-dasharray=\"6 3\""),
            false => (COLORS[k % COLORS.len()], ""),
        };
        let at: Vec<(f64, f64)> = s.points.iter().map(|&(x, y)| (sx(x), sy(y))).collect();
        let path: Vec<String> = at.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
        svg += &format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"2\"{dash}/>\n",
            path.join(" ")
        );
        // A marker on every point: a line of one point (a sweep cut short) still shows.
        if !s.front {
            for (x, y) in &at {
                svg +=
                    &format!("<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"2.5\" fill=\"{color}\"/>\n");
            }
        }
        svg += &format!(
            "<text x=\"{}\" y=\"{}\" fill=\"{color}\">{}</text>\n",
            RIGHT + 12.0,
            MARGIN + 16.0 * (k as f64 + 1.0),
            s.name
        );
    }
    svg + "</svg>\n"
}
