//! `stridekit calibrate foot`: learn a foot IMU's accelerometer-to-gyroscope alignment
//! from level walks ([`learn`]), then render the calibration file's text, the report
//! (a table per walk, each walk alone, a warning when they disagree) and the plot of
//! every stance's height before and after.

use std::path::{Path, PathBuf};

use stridekit_core::foot::{FootConfig, FootSample};
use stridekit_formats::read_foot_csv;

use super::foot_config::{config_for, FootOptions};
use crate::foot::alignment::{learn as fit_alignment, LevelFit};
use crate::foot::device::evidence;
use crate::report::{line_chart, Chart, Series, Style, YFormat, PALETTE};
use crate::table::Table;

/// Walks whose alignments alone differ by more than this are questioned, degrees.
const DISAGREE_DEG: f64 = 0.5;

/// What the walks taught.
pub struct FootCalibration {
    pub files: Vec<PathBuf>,
    /// The device assumptions per walk, as [`config_for`] says them.
    pub described: Vec<String>,
    /// The fit over all the walks.
    pub fit: LevelFit,
    /// Each walk's own pitch alignment, rad (with more than one walk).
    pub alone_rad: Vec<(String, f64)>,
}

/// Learns the alignment from `files` (one device: one layout, its evidence from all
/// the walks), with the axes and IMU profile of `o`.
pub fn learn(files: &[PathBuf], o: &FootOptions) -> Result<FootCalibration, String> {
    let recs = files
        .iter()
        .map(|file| read_foot_csv(file).map_err(|e| format!("{}: {e}", file.display())))
        .collect::<Result<Vec<_>, _>>()?;
    let device = evidence(&recs.iter().collect::<Vec<_>>());
    let mut walks: Vec<(String, Vec<FootSample>)> = Vec::new();
    let mut described = Vec::new();
    let mut config: Option<FootConfig> = None;
    for (file, rec) in files.iter().zip(recs) {
        let (c, text) = config_for(o, rec.format, &device)?;
        if config.as_ref().is_some_and(|k| *k != c) {
            return Err(format!(
                "{}: another layout than the first file (give --axes and --imu)",
                file.display()
            ));
        }
        described.push(text);
        let samples = (0..rec.len())
            .map(|i| crate::foot::eval::foot_sample(&rec, i))
            .collect();
        walks.push((rec.name.clone(), samples));
        config = Some(c);
    }
    let config = config.ok_or("no walk given")?;
    let fit = fit_alignment(&config, &walks)?;
    let alone_rad = each_alone(&config, &walks)?;
    Ok(FootCalibration {
        files: files.to_vec(),
        described,
        fit,
        alone_rad,
    })
}

/// Each walk alone (with more than one): a device constant agrees between walks; when
/// the angles scatter, the height error is not (only) this alignment.
fn each_alone(
    config: &FootConfig,
    walks: &[(String, Vec<FootSample>)],
) -> Result<Vec<(String, f64)>, String> {
    if walks.len() < 2 {
        return Ok(Vec::new());
    }
    walks
        .iter()
        .map(|w| {
            let f = fit_alignment(config, std::slice::from_ref(w))?;
            Ok((w.0.clone(), f.alignment_rad[1]))
        })
        .collect()
}

impl FootCalibration {
    /// The calibration file's text (versioned).
    pub fn text(&self) -> String {
        let names: Vec<String> = self.files.iter().map(|f| f.display().to_string()).collect();
        crate::foot::alignment::to_text(
            self.fit.alignment_rad,
            &format!(
                "accelerometer-to-gyroscope alignment learned by `stridekit calibrate foot` from the level walks:\n{}\naxes and IMU profile: as described when replaying with --calibration",
                names.join("\n")
            ),
        )
    }

    /// The report; `svg` names the stance-height plot.
    pub fn report(&self, svg: &Path) -> String {
        let mut report = String::new();
        for (file, described) in self.files.iter().zip(&self.described) {
            report += &format!("{}: {described}\n", file.display());
        }
        let a = self.fit.alignment_rad;
        report += &format!(
            "accelerometer alignment (rotation vector, body axes x forward, y left, z up; \
             the angle about y fitted): ({:.3}°, {:.3}°, {:.3}°), {} iterations\n",
            a[0].to_degrees(),
            a[1].to_degrees(),
            a[2].to_degrees(),
            self.fit.iterations
        );
        report += &self.walk_table().render();
        report += &self.agreement();
        report += &format!("stance heights before and after: {}\n", svg.display());
        report
    }

    /// One row per walk: its steps, distance, and the height errors before → after.
    fn walk_table(&self) -> Table {
        let mut t = Table::new([
            "walk",
            "stance-to-stance steps",
            "distance",
            "RMS height change per step, before → after",
            "height end − start",
            "3-D end − start",
        ]);
        for w in &self.fit.walks {
            let pct = |x: f64| 100.0 * x / w.distance_m.max(1e-9);
            t.row([
                w.name.clone(),
                w.steps.to_string(),
                format!("{:.2} m", w.distance_m),
                format!(
                    "{:.1} → {:.1} mm",
                    1e3 * w.rms_before_m,
                    1e3 * w.rms_after_m
                ),
                format!("{:+.3} → {:+.3} m", w.height_before_m, w.height_after_m),
                format!(
                    "{:.2} → {:.2} %",
                    pct(w.closure_before_m),
                    pct(w.closure_after_m)
                ),
            ]);
        }
        t
    }

    /// Each walk's own angle, and a warning when they disagree by over
    /// [`DISAGREE_DEG`].
    fn agreement(&self) -> String {
        let mut text = String::new();
        if self.alone_rad.is_empty() {
            return text;
        }
        for (name, a) in &self.alone_rad {
            text += &format!("  {name} alone: {:.3}°\n", a.to_degrees());
        }
        let (lo, hi) = self
            .alone_rad
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (_, v)| {
                (l.min(*v), h.max(*v))
            });
        if (hi - lo).to_degrees() > DISAGREE_DEG {
            text += &format!(
                "warning: the walks alone disagree by {:.2}° (over {DISAGREE_DEG}°): their \
                 height errors are not (only) a constant alignment of this IMU; check the \
                 calibration on another level walk before using it\n",
                (hi - lo).to_degrees()
            );
        }
        text
    }

    /// Every stance's height over time, per walk, with the starting alignment (dots)
    /// and the fitted one (line): a level walk's stances should lie on zero.
    pub fn plot(&self, path: &Path) -> Result<(), String> {
        let mut series = Vec::new();
        for (i, w) in self.fit.walks.iter().enumerate() {
            let c = PALETTE[i % PALETTE.len()];
            series.push(Series {
                name: format!("{} before", w.name),
                points: w.stances_before.clone(),
                color: Some(c),
                style: Style::Points,
            });
            series.push(Series {
                name: format!("{} calibrated", w.name),
                points: w.stances_after.clone(),
                color: Some(c),
                style: Style::Line,
            });
        }
        line_chart(
            path,
            &Chart {
                title: "stance heights above the first stance (a level walk: 0)",
                x_label: "time since the walk's start (s)",
                y_label: "height (m)",
                series: &series,
                bands: &[],
                y_range: None,
                y_format: YFormat::Number,
            },
        )
        .map_err(|e| format!("{}: {e}", path.display()))
    }
}
