//! Rendered images against float references: half-float OpenEXR files
//! compared in linear values, within a tolerance stated for each reference.
//!
//! Half floats keep about three significant digits at any magnitude up to
//! 65504, so a value of 4.0 is compared as closely as one of 0.4: nothing
//! above 1.0 is clipped before the comparison (8-bit sRGB PNGs clipped a
//! fifth to a half of the pixels of the HDR references at 255). A failure
//! names the worst pixels (where, expected, got, difference) and leaves the
//! rendered image, the reference and a difference image in a folder of its
//! own under the target dir, never in the source tree.

use std::path::{Path, PathBuf};

use exr::prelude::{
    Encoding as ExrEncoding, Image as ExrImage, SpecificChannels, Vec2, WritableImage, f16,
    read_first_rgba_layer_from_file,
};
use spreadlight_render::image_io::{Encoding, write_image};
use spreadlight_render::readback::ImageF32;

/// The environment variable that re-makes the references instead of comparing.
pub const BLESS: &str = "SPREADLIGHT_BLESS";

/// How far a rendered image may be from its reference, and why that far.
///
/// A channel matches when `|got - expected| <= absolute + relative * |expected|`;
/// a pixel matches when all four channels do; at most `outliers` of the
/// pixels may not.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Slack of every channel in linear units, whatever its value: for
    /// values near 0, where a relative slack is none.
    pub absolute: f32,
    /// Further slack as a share of the expected value, so HDR values get
    /// proportionally more. Never below 1e-3, twice a half float's rounding.
    pub relative: f32,
    /// Share of pixels that may be outside the slack: edge pixels that
    /// another rasterizer covers differently, not drift.
    pub outliers: f64,
    /// Why this much: printed with a failure.
    pub why: &'static str,
}

impl Tolerance {
    fn slack(&self, expected: f32) -> f32 {
        self.absolute + self.relative * expected.abs()
    }
}

/// One pixel of a comparison, with its difference.
#[derive(Clone, Copy, Debug)]
pub struct PixelDifference {
    pub x: u32,
    pub y: u32,
    pub expected: [f32; 4],
    pub got: [f32; 4],
    /// The largest `|got - expected| / slack` of its channels: above 1 it
    /// is outside the tolerance (infinite for a NaN).
    pub excess: f32,
}

impl PixelDifference {
    pub fn difference(&self) -> [f32; 4] {
        std::array::from_fn(|c| self.got[c] - self.expected[c])
    }
}

/// What a comparison found.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub pixels: usize,
    /// Pixels with a channel outside the tolerance.
    pub outside: usize,
    /// The pixels that differ most (by excess), worst first.
    pub worst: Vec<PixelDifference>,
    /// The largest and mean absolute difference of any channel.
    pub max_difference: f32,
    pub mean_difference: f32,
    /// Per pixel: `|got - expected|` per channel.
    pub difference: ImageF32,
    /// Per pixel: the largest excess of its channels.
    pub excess: Vec<f32>,
}

impl Comparison {
    pub fn outside_share(&self) -> f64 {
        self.outside as f64 / self.pixels.max(1) as f64
    }

    pub fn passes(&self, tolerance: &Tolerance) -> bool {
        self.outside_share() <= tolerance.outliers
    }
}

/// How many of the worst pixels a report names.
const WORST: usize = 8;

/// Compare `got` with `expected` (same size) channel by channel.
pub fn compare(expected: &ImageF32, got: &ImageF32, tolerance: &Tolerance) -> Comparison {
    assert_eq!(
        (expected.width, expected.height),
        (got.width, got.height),
        "compare: the images differ in size"
    );
    let mut all = Vec::with_capacity(got.pixels.len());
    let mut difference = Vec::with_capacity(got.pixels.len());
    let (mut max_difference, mut sum) = (0.0f32, 0.0f64);
    for (i, (e, g)) in expected.pixels.iter().zip(&got.pixels).enumerate() {
        let d: [f32; 4] = std::array::from_fn(|c| (g[c] - e[c]).abs());
        let excess = (0..4)
            .map(|c| {
                if d[c].is_nan() {
                    f32::INFINITY
                } else {
                    d[c] / tolerance.slack(e[c])
                }
            })
            .fold(0.0f32, f32::max);
        for v in d {
            max_difference = max_difference.max(if v.is_nan() { f32::INFINITY } else { v });
            sum += f64::from(v);
        }
        difference.push(d);
        all.push(PixelDifference {
            x: i as u32 % got.width,
            y: i as u32 / got.width,
            expected: *e,
            got: *g,
            excess,
        });
    }
    let excess: Vec<f32> = all.iter().map(|p| p.excess).collect();
    let outside = excess.iter().filter(|e| **e > 1.0).count();
    all.sort_by(|a, b| b.excess.total_cmp(&a.excess));
    all.truncate(WORST);
    Comparison {
        pixels: got.pixels.len(),
        outside,
        worst: all,
        max_difference,
        mean_difference: (sum / (got.pixels.len() * 4).max(1) as f64) as f32,
        difference: ImageF32 {
            width: got.width,
            height: got.height,
            pixels: difference,
        },
        excess,
    }
}

/// The comparison in words: the counts, the tolerance and why, and the worst
/// pixels with their expected and rendered values.
pub fn report(name: &str, comparison: &Comparison, tolerance: &Tolerance) -> String {
    let fmt = |v: [f32; 4]| format!("({:.4}, {:.4}, {:.4}, {:.4})", v[0], v[1], v[2], v[3]);
    let mut text = format!(
        "{name}: {} of {} pixels ({:.2}%) outside the tolerance (|d| <= {} + {} * |expected| per \
         channel; {:.2}% allowed: {}); largest difference {:.4}, mean {:.5}.\nWorst pixels (x, y: \
         expected -> got, difference, times the slack):",
        comparison.outside,
        comparison.pixels,
        comparison.outside_share() * 100.0,
        tolerance.absolute,
        tolerance.relative,
        tolerance.outliers * 100.0,
        tolerance.why,
        comparison.max_difference,
        comparison.mean_difference,
    );
    for p in &comparison.worst {
        text += &format!(
            "\n  {:>3}, {:>3}: {} -> {}, {}, {:.1}x",
            p.x,
            p.y,
            fmt(p.expected),
            fmt(p.got),
            fmt(p.difference()),
            p.excess
        );
    }
    text
}

/// `image` with every channel rounded to a half float, as a reference stores it.
pub fn to_half(image: &ImageF32) -> ImageF32 {
    ImageF32 {
        width: image.width,
        height: image.height,
        pixels: image
            .pixels
            .iter()
            .map(|p| p.map(|v| f16::from_f32(v).to_f32()))
            .collect(),
    }
}

/// Write `image` as a half-float RGBA OpenEXR file, ZIP-compressed (lossless
/// on the halves, and the same bytes for the same image, so a re-blessed
/// reference that did not change shows no change in git).
pub fn write_exr(image: &ImageF32, path: &Path) -> Result<(), String> {
    let width = image.width as usize;
    let channels = SpecificChannels::rgba(|p: Vec2<usize>| {
        let v = image.pixels[p.y() * width + p.x()].map(f16::from_f32);
        (v[0], v[1], v[2], v[3])
    });
    ExrImage::from_encoded_channels(
        (width, image.height as usize),
        ExrEncoding::SMALL_LOSSLESS,
        channels,
    )
    .write()
    .to_file(path)
    .map_err(|e| format!("{}: {e}", path.display()))
}

/// Read the first RGBA layer of an OpenEXR file as linear floats.
pub fn read_exr(path: &Path) -> Result<ImageF32, String> {
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| ImageF32 {
            width: resolution.width() as u32,
            height: resolution.height() as u32,
            pixels: vec![[0.0; 4]; resolution.width() * resolution.height()],
        },
        |image: &mut ImageF32, p, (r, g, b, a): (f32, f32, f32, f32)| {
            let i = p.y() * image.width as usize + p.x();
            image.pixels[i] = [r, g, b, a];
        },
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The difference as a picture: within the tolerance grey (brighter the
/// nearer the limit, black where equal), outside it red.
fn excess_picture(comparison: &Comparison) -> ImageF32 {
    ImageF32 {
        width: comparison.difference.width,
        height: comparison.difference.height,
        pixels: comparison
            .excess
            .iter()
            .map(|&e| {
                if e > 1.0 {
                    [1.0, 0.0, 0.0, 1.0]
                } else {
                    let v = e * 0.6;
                    [v, v, v, 1.0]
                }
            })
            .collect(),
    }
}

/// Where a reference lives and where a run leaves what it rendered.
pub struct References {
    /// The folder of `NAME.exr` files, in the source tree.
    pub folder: PathBuf,
    /// A folder under the target dir: each reference's run leaves its
    /// images in `artifacts/NAME/`.
    pub artifacts: PathBuf,
}

impl References {
    pub fn reference(&self, name: &str) -> PathBuf {
        self.folder.join(format!("{name}.exr"))
    }

    /// Check `image` against the reference `name`, or re-make the reference
    /// when `SPREADLIGHT_BLESS` is set. Either way `artifacts/NAME/` holds
    /// `rendered.exr` and previews to look at (`rendered.png`, encoded as
    /// the Output asks, and, when comparing, `reference.png`,
    /// `difference.exr` with `|got - expected|` per channel and
    /// `difference.png`, red where a pixel is outside the tolerance).
    /// Panics with the report when the image is not within `tolerance`.
    pub fn check(&self, name: &str, image: &ImageF32, encoding: Encoding, tolerance: &Tolerance) {
        if let Err(report) = self.try_check(name, image, encoding, tolerance) {
            panic!("{report}");
        }
    }

    /// [`References::check`], with the report of an image outside the
    /// tolerance returned (a missing or unreadable reference still panics).
    pub fn try_check(
        &self,
        name: &str,
        image: &ImageF32,
        encoding: Encoding,
        tolerance: &Tolerance,
    ) -> Result<(), String> {
        assert!(
            tolerance.relative >= 1e-3,
            "{name}: a relative tolerance under 1e-3 is below a half float's rounding"
        );
        let got = to_half(image);
        // A share of pixels free that is more than a quarter of what the
        // image shows (pixels with a channel beyond the absolute slack)
        // would let the content go and still pass.
        let shown = got
            .pixels
            .iter()
            .filter(|p| p[..3].iter().any(|v| v.abs() > tolerance.absolute))
            .count();
        let free = (tolerance.outliers * got.pixels.len() as f64).floor() as usize;
        assert!(
            free * 4 <= shown,
            "{name}: the image shows {shown} of {} pixels, too few for {free} pixels free: \
             make the content larger or the tolerance tighter",
            got.pixels.len()
        );
        let out = self.artifacts.join(name);
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(&out).unwrap_or_else(|e| panic!("{}: {e}", out.display()));
        let save = |image: &ImageF32, file: &str, encoding: Encoding| {
            let path = out.join(file);
            let written = if file.ends_with(".exr") {
                write_exr(image, &path)
            } else {
                write_image(image, &path, encoding).map_err(|e| e.to_string())
            };
            written.unwrap_or_else(|e| panic!("{name}: {e}"));
        };
        save(&got, "rendered.exr", encoding);
        save(&got, "rendered.png", encoding);
        let reference = self.reference(name);
        if std::env::var_os(BLESS).is_some() {
            std::fs::create_dir_all(&self.folder).expect("the references' folder");
            write_exr(&got, &reference).unwrap_or_else(|e| panic!("bless {name}: {e}"));
            return Ok(());
        }
        let expected = read_exr(&reference).unwrap_or_else(|e| {
            panic!("{e}; make it with {BLESS}=1 (and look at it before committing it)")
        });
        assert_eq!(
            (expected.width, expected.height),
            (got.width, got.height),
            "{name}: the image is {}x{}, the reference {} is {}x{}",
            got.width,
            got.height,
            reference.display(),
            expected.width,
            expected.height
        );
        let comparison = compare(&expected, &got, tolerance);
        save(&expected, "reference.png", encoding);
        save(&comparison.difference, "difference.exr", encoding);
        save(
            &excess_picture(&comparison),
            "difference.png",
            Encoding::Linear,
        );
        if comparison.passes(tolerance) {
            return Ok(());
        }
        Err(format!(
            "{}\nThe rendered image, the reference and the difference are in {}; {}=1 \
             re-makes the reference after an intended change.",
            report(name, &comparison, tolerance),
            out.display(),
            BLESS
        ))
    }
}
