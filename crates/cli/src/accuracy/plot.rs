//! The accuracy/cost plot every effect's table comes with: GPU time (x)
//! against error (y), one line per series (a mode, a filter, temporal on or
//! off), a point per quality setting. SVG through plotters, so it needs no
//! fonts and diffs as text.

use std::path::Path;

use anyhow::Context;
use plotters::prelude::*;

/// One line of the plot: its name and (ms, error, label) points.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64, String)>,
}

impl Series {
    /// Points gathered into series by name, in first-seen order: one line per
    /// method, one point per quality setting.
    pub fn group(points: impl IntoIterator<Item = (String, (f64, f64, String))>) -> Vec<Series> {
        let mut series: Vec<Series> = Vec::new();
        for (name, point) in points {
            match series.iter_mut().find(|s| s.name == name) {
                Some(s) => s.points.push(point),
                None => series.push(Series {
                    name,
                    points: vec![point],
                }),
            }
        }
        series
    }
}

/// Write `series` as an SVG plot of `y_label` against GPU ms to `file`.
pub fn write_svg(file: &Path, title: &str, y_label: &str, series: &[Series]) -> anyhow::Result<()> {
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| (p.0, p.1)))
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    anyhow::ensure!(!all.is_empty(), "nothing to plot for {title}");
    let max_x = all.iter().map(|p| p.0).fold(0.0, f64::max) * 1.1 + 1e-3;
    let max_y = all.iter().map(|p| p.1).fold(0.0, f64::max) * 1.1 + 1e-4;
    if let Some(parent) = file.parent() {
        std::fs::create_dir_all(parent).ok();
    }
    let root = SVGBackend::new(file, (800, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..max_x, 0.0..max_y)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("GPU ms")
        .y_desc(y_label)
        .draw()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    for (k, s) in series.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|p| (p.0, p.1))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(|e| anyhow::anyhow!("{e}"))?
            .label(s.name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
            });
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        chart
            .draw_series(
                s.points
                    .iter()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .map(|p| {
                        Text::new(
                            p.2.clone(),
                            (p.0, p.1),
                            ("sans-serif", 11).into_font().color(&BLACK),
                        )
                    }),
            )
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    root.present()
        .with_context(|| format!("cannot write {}", file.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_an_svg_with_every_series() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plot.svg");
        let series = vec![
            Series {
                name: "temporal".into(),
                points: vec![(0.1, 0.05, "4".into()), (0.2, 0.03, "8".into())],
            },
            Series {
                name: "single frame".into(),
                points: vec![(0.1, 0.08, "4".into()), (f64::NAN, 0.1, "bad".into())],
            },
        ];
        write_svg(&file, "AO", "RMSE", &series).unwrap();
        let svg = std::fs::read_to_string(&file).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40.min(svg.len())]);
        assert!(svg.contains("temporal") && svg.contains("single frame"));
    }

    #[test]
    fn nothing_to_plot_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let err = write_svg(&dir.path().join("p.svg"), "AO", "RMSE", &[]).unwrap_err();
        assert!(err.to_string().contains("nothing to plot"));
    }
}
